#include <cstring>

#include "commands.h"

int main(int argc, char** argv) {
  using namespace detexture::app;
  if (argc >= 2 && std::strcmp(argv[1], "synth") == 0) return run_synth(argc - 1, argv + 1);
  if (argc >= 2 && std::strcmp(argv[1], "compare") == 0) return run_compare(argc - 1, argv + 1);
  if (argc >= 2 && std::strcmp(argv[1], "render") == 0) return run_render(argc - 1, argv + 1);
  return run_detexture(argc, argv);
}
