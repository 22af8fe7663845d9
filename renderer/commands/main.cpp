// isotrace: one executable, one subcommand per file in this folder.
#include "renderer/commands/command.h"
#include "renderer/memory_pages.h"

int main(int argc, char** argv) {
    isotrace::keepFreedMemoryForReuse();
    return isotrace::runIsotrace(argc, argv);
}
