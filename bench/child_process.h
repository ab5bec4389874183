// Runs this executable again as a child process (fork/exec of /proc/self/exe) and
// collects what it writes to stdout; its stderr goes to ours. Linux only; call
// from one thread at a time.
#pragma once

#include <string>
#include <vector>

namespace penumbra::bench {

struct ChildResult {
  int exitCode = -1;   // the child's exit status; -1 if it died of a signal
  int signal = 0;      // the signal that ended it, else 0
  std::string output;  // everything it wrote to stdout
};

// `arguments` follow the program name (argv[1] onwards). Throws std::runtime_error
// if the child cannot be started.
ChildResult runSelf(const std::vector<std::string>& arguments);

}  // namespace penumbra::bench
