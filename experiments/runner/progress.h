// One progress line on stderr: "<label> <done>/<total> <detail>, ETA <s> s".
// Rewritten in place on a terminal; on a log (CI) a line every ~10 %.
#pragma once

#include <chrono>
#include <ostream>
#include <string>

namespace glintlab {

class Progress {
 public:
  Progress(std::ostream& log, std::string label, int total);
  // One more unit of work done; `detail` names it (variant, frame, cost).
  void step(const std::string& detail);

 private:
  std::ostream& log_;
  std::string label_;
  int total_, done_ = 0;
  bool tty_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace glintlab
