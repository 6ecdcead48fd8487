// The subcommands of the detexture executable. main() dispatches on argv[1]:
// "synth", "compare" and "render" go to their own command, anything else is the
// texture-removal job. Each returns the process exit code.
#pragma once

namespace detexture::app {

/// Exit codes, documented in README.md.
enum ExitCode : int {
  kExitOk = 0,
  kExitFailure = 1,   ///< unexpected internal error
  kExitUsage = 2,     ///< bad command line or parameter value
  kExitInput = 3,     ///< the input file is missing, unreadable or malformed
  kExitOutput = 4,    ///< an output cannot be written, or would overwrite the input or an output
  kExitResource = 5,  ///< a resource limit: memory (--memory-limit, out of memory) or threads
};

int run_detexture(int argc, char** argv);
int run_synth(int argc, char** argv);    ///< argv[0] is "synth"
int run_compare(int argc, char** argv);  ///< argv[0] is "compare"
int run_render(int argc, char** argv);   ///< argv[0] is "render"

}  // namespace detexture::app
