// A progress bar on stderr for long stages, shown only on a TTY and without --quiet.
#pragma once

#include <string>

#include "cli/interrupt.hpp"
#include "uavcover/uavcover.hpp"

namespace uavcover::cli {

/// Returns a Progress callback drawing a bar, or an empty callback when quiet or not a TTY.
Progress make_progress_bar(bool quiet);
/// Ends the bar's line (if one was drawn).
void finish_progress_bar();

/// Runs work(ctx) with a progress bar (unless quiet) and the Ctrl-C stop token in ctx, ending the
/// bar's line whether the work returns or throws.
template <class Work>
auto with_progress(bool quiet, Work&& work) {
  struct Finish {
    ~Finish() { finish_progress_bar(); }
  } finish;
  return work(Context(make_progress_bar(quiet), interrupt_token()));
}

}  // namespace uavcover::cli
