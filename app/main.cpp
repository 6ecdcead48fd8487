#include <cstdio>
#include <cstring>

#include "commands.h"
#include "detexture_version.h"

int main(int argc, char** argv) {
  using namespace detexture::app;
  if (argc >= 2 &&
      (std::strcmp(argv[1], "--version") == 0 || std::strcmp(argv[1], "version") == 0)) {
    std::printf("detexture %s (commit %s)\n", DETEXTURE_VERSION, DETEXTURE_COMMIT);
    return kExitOk;
  }
  if (argc >= 2 && std::strcmp(argv[1], "help") == 0) {
    // `detexture help [COMMAND]`: the same text as `detexture [COMMAND] --help`.
    char help_flag[] = "--help";
    if (argc >= 3) {
      char* sub[] = {argv[2], help_flag, nullptr};
      if (std::strcmp(argv[2], "synth") == 0) return run_synth(2, sub);
      if (std::strcmp(argv[2], "compare") == 0) return run_compare(2, sub);
      if (std::strcmp(argv[2], "render") == 0) return run_render(2, sub);
      std::fprintf(stderr, "detexture: no command '%s'; the commands are synth, compare, render\n",
                   argv[2]);
      return kExitUsage;
    }
    char* args[] = {argv[0], help_flag, nullptr};
    return run_detexture(2, args);
  }
  if (argc >= 2 && std::strcmp(argv[1], "synth") == 0) return run_synth(argc - 1, argv + 1);
  if (argc >= 2 && std::strcmp(argv[1], "compare") == 0) return run_compare(argc - 1, argv + 1);
  if (argc >= 2 && std::strcmp(argv[1], "render") == 0) return run_render(argc - 1, argv + 1);
  return run_detexture(argc, argv);
}
