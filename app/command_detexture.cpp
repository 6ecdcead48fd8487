// Placeholder during initial development; replaced by the real command.
#include <cstdio>
#include "commands.h"
namespace detexture::app {
int run_detexture(int, char**) { std::fputs("detexture: 'detexture' is not built yet\n", stderr); return kExitFailure; }
}  // namespace detexture::app
