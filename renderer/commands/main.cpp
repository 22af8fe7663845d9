// isotrace: one executable, one subcommand per file in this folder.
#include <cstring>

#include "renderer/commands/command.h"
#include "renderer/commands/embree_on_demand.h"
#include "renderer/memory_pages.h"

namespace {

// The commands that trace rays. Only a hint, read before the command line
// is parsed: any command loads Embree on its first call if this guessed
// wrong.
bool tracesRays(int argc, char** argv) {
    if (argc < 2) return false;
    for (const char* command : {"render", "preview"})
        if (std::strcmp(argv[1], command) == 0) return true;
    return false;
}

}  // namespace

int main(int argc, char** argv) {
    isotrace::keepFreedMemoryForReuse();
    if (tracesRays(argc, argv)) isotrace::startLoadingEmbree();
    const int status = isotrace::runIsotrace(argc, argv);
    isotrace::finishLoadingEmbree();
    return status;
}
