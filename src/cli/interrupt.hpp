// Ctrl-C (SIGINT) and SIGTERM become a stop request: long work ends cleanly at its next check
// (Context), nothing partial is written, and the command exits with 130. A second Ctrl-C exits at once.
#pragma once

#include <stop_token>

namespace uavcover::cli {

/// Blocks SIGINT/SIGTERM in every thread and starts the thread that waits for them. Call once at
/// the start of main(), before any other thread exists.
void install_interrupt_handler();

/// Stopped when SIGINT or SIGTERM arrives.
std::stop_token interrupt_token();

}  // namespace uavcover::cli
