#pragma once
// Semantic checks of the numbers a user gives in a config file, in one place for every command: each number is
// finite and each known key lies in its range (relations between keys, such as stereo.min_depth < max_depth, are
// checked on the parsed values by system::load_vo_config). A failure
// throws std::runtime_error naming the file, the dotted key path, its line and the allowed range. Type errors and
// unknown keys are caught elsewhere (param() and KeyReadLog); calibration values by validate_calibration.
#include <string>

#include "io/config.hpp"

namespace vkvo::io {

// Throws on the first non-finite number anywhere in the file, or a known key outside its range.
void validate_config_values(const Config& config);

// "file: key.path (line N): problem"; the line is left out when `node` carries no position.
std::string config_error_message(const std::string& origin, const std::string& key_path, const YAML::Node& node,
                                 const std::string& problem);

}  // namespace vkvo::io
