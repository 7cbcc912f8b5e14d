#pragma once
// The CLI's exit codes (docs/bad-input.md): scripts can tell bad input from a run that produced nothing usable.

namespace vkvo::app {

inline constexpr int kExitOk = 0;
inline constexpr int kExitBadInput = 1;     // unreadable or invalid input, config, calibration or options
inline constexpr int kExitNoResult = 2;     // the run finished but produced nothing usable (no frame tracked)
inline constexpr int kExitWriteFailed = 3;  // an output file could not be written
// A run stopped by SIGINT, SIGTERM or SIGHUP exits with 128 + the signal number, after writing what it has.

inline constexpr const char* kExitCodeHelp =
    "Exit codes: 0 success; 1 bad input (file, config, calibration or option); 2 the run produced nothing usable "
    "(no frame tracked); 3 an output could not be written; 128+N stopped by signal N (outputs written).";

}  // namespace vkvo::app
