// isotrace: one executable, one subcommand per file in this folder.
#include "renderer/commands/command.h"

int main(int argc, char** argv) { return isotrace::runIsotrace(argc, argv); }
