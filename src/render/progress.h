// progress.h — the progress line on stderr.
//
// On a terminal: one line rewritten in place ("\r") at most ~8 times a second; otherwise (a
// pipe, a log file): a plain line every second. It shows samples per pixel done / total
// (fractional while one pass takes several waves of the path pool, e.g. "0.42/1 spp"),
// elapsed time, ETA, Mrays/s and a note (the error against a reference). The ETA comes from
// a moving average of the recent steps' seconds per spp (step()), leaving out the first
// step, which includes the kernels' JIT; before a second step it is elapsed / done. Disabled
// entirely when constructed with enabled = false.
#pragma once

#include <cstdint>
#include <deque>
#include <string>
#include <utility>

#include "util/timer.h"

namespace wp::render {

class Progress {
  public:
    Progress(int total_samples, double time_limit_s, bool enabled);
    // True when update() would print now (lets the caller skip reading the ray count).
    bool due() const;
    void update(double samples_done, std::uint64_t rays);
    // A finished step of `spp` samples per pixel that took `seconds` (for the ETA).
    void step(double spp, double seconds);
    // Text appended to the line from now on (e.g. the error against a reference).
    void set_note(std::string note) { note_ = std::move(note); }
    // No sample total to count towards (render --target-error without --spp): the line shows
    // the samples done, and an ETA only for a time limit.
    void set_open_ended() { open_ended_ = true; }
    // Prints the final state and ends the line; `interrupted` adds "interrupted at N spp".
    void finish(double samples_done, std::uint64_t rays, bool interrupted = false);

    static constexpr std::size_t kAverageSteps = 8;  // steps in the moving average

  private:
    std::string line(double samples_done, std::uint64_t rays) const;
    int total_;
    double time_limit_s_;
    bool enabled_;
    bool tty_;
    bool printed_ = false;
    std::string note_;
    bool open_ended_ = false;
    Timer timer_;
    double last_print_s_ = -1e9;
    int steps_seen_ = 0;
    std::deque<std::pair<double, double>> recent_;  // (spp, seconds) of the latest steps
};

}  // namespace wp::render
