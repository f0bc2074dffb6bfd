#include "experiments/runner/progress.h"

#include <cmath>
#include <iostream>
#include <unistd.h>

namespace glintlab {

Progress::Progress(std::ostream& log, std::string label, int total)
    : log_(log), label_(std::move(label)), total_(total), tty_(&log == &std::cerr && isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()) {}

void Progress::step(const std::string& detail) {
  ++done_;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double eta = done_ > 0 ? elapsed * double(total_ - done_) / double(done_) : 0.0;
  const std::string line = label_ + " " + std::to_string(done_) + "/" + std::to_string(total_) + "  " + detail +
                           ", ETA " + std::to_string(int(std::lround(eta))) + " s";
  if (tty_) {
    log_ << "\r" << line << "\033[K" << std::flush;
    if (done_ == total_) log_ << "\n";
  } else if (done_ == total_ || done_ == 1 || done_ * 10 / total_ != (done_ - 1) * 10 / total_) {
    log_ << line << "\n" << std::flush;
  }
}

}  // namespace glintlab
