#include "cli/interrupt.hpp"

#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <thread>

namespace uavcover::cli {

namespace {

std::stop_source& source() {
  static std::stop_source s;
  return s;
}

}  // namespace

void install_interrupt_handler() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  std::thread([set] {
    int sig = 0;
    int seen = 0;
    while (sigwait(&set, &sig) == 0) {
      if (++seen > 1) _exit(130);  // a second Ctrl-C: the user insists
      source().request_stop();
    }
  }).detach();
}

std::stop_token interrupt_token() { return source().get_token(); }

}  // namespace uavcover::cli
