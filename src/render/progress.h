// progress.h — the progress line on stderr.
//
// On a terminal: one line rewritten in place ("\r") at most ~8 times a second with samples
// done / total, elapsed time, ETA and Mrays/s. Otherwise (a pipe, a log file): a plain
// line every ~2 seconds. Disabled entirely when constructed with enabled = false.
#pragma once

#include <cstdint>
#include <string>
#include <utility>

#include "util/timer.h"

namespace wp::render {

class Progress {
  public:
    Progress(int total_samples, double time_limit_s, bool enabled);
    // True when update() would print now (lets the caller skip reading the ray count).
    bool due() const;
    void update(int samples_done, std::uint64_t rays);
    // Text appended to the line from now on (e.g. the error against a reference).
    void set_note(std::string note) { note_ = std::move(note); }
    // Prints the final state and ends the line.
    void finish(int samples_done, std::uint64_t rays);

  private:
    std::string line(int samples_done, std::uint64_t rays) const;
    int total_;
    double time_limit_s_;
    bool enabled_;
    bool tty_;
    bool printed_ = false;
    std::string note_;
    Timer timer_;
    double last_print_s_ = -1e9;
};

}  // namespace wp::render
