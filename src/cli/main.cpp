#include "cli/commands.h"

int main(int argc, char** argv) { return sscs::run_cli(argc, argv); }
