// The command-line conventions (gvs/daemon/command_line.hpp), by their
// names in the gvs tool's namespace.
#pragma once

#include "gvs/daemon/command_line.hpp"

namespace gvs::cli {

using daemon::check_subcommands;
using daemon::kUsageExitCode;
using daemon::method_check;
using daemon::method_list;
using daemon::number_in;
using daemon::positive_number;
using daemon::seed_number;
using daemon::usage_exit;
using daemon::version_text;
using daemon::whole_number_in;

}  // namespace gvs::cli
