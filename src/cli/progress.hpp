// A progress bar on stderr for long stages, shown only on a TTY and without --quiet.
#pragma once

#include <string>

#include "uavcover/uavcover.hpp"

namespace uavcover::cli {

/// Returns a Progress callback drawing a bar, or an empty callback when quiet or not a TTY.
Progress make_progress_bar(bool quiet);
/// Ends the bar's line (if one was drawn).
void finish_progress_bar();

}  // namespace uavcover::cli
