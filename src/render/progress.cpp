#include "render/progress.h"

#include <cstdio>

#include <algorithm>

#include <fmt/format.h>
#include <unistd.h>

namespace wp::render {

namespace {

std::string format_duration(double s) {
    if (s < 60.0) return fmt::format("{:.1f}s", s);
    int t = static_cast<int>(s + 0.5);
    if (t < 3600) return fmt::format("{}m{:02d}s", t / 60, t % 60);
    return fmt::format("{}h{:02d}m", t / 3600, (t / 60) % 60);
}

}  // namespace

Progress::Progress(int total_samples, double time_limit_s, bool enabled)
    : total_(total_samples), time_limit_s_(time_limit_s), enabled_(enabled),
      tty_(isatty(fileno(stderr)) != 0) {}

bool Progress::due() const {
    if (!enabled_) return false;
    return timer_.seconds() - last_print_s_ >= (tty_ ? 0.125 : 2.0);
}

std::string Progress::line(int done, std::uint64_t rays) const {
    double el = timer_.seconds();
    double eta = done > 0 ? el / done * (total_ - done) : 1e30;
    if (time_limit_s_ > 0.0) eta = std::min(eta, std::max(0.0, time_limit_s_ - el));
    double mrays = el > 0.0 ? rays / el * 1e-6 : 0.0;
    return fmt::format("render: {}/{} spp ({:3.0f}%)  elapsed {}  ETA {}  {:.1f} Mrays/s{}{}",
                       done, total_, 100.0 * done / std::max(total_, 1), format_duration(el),
                       done > 0 || time_limit_s_ > 0.0 ? format_duration(eta) : "?", mrays,
                       note_.empty() ? "" : "  ", note_);
}

void Progress::update(int done, std::uint64_t rays) {
    if (!due()) return;
    last_print_s_ = timer_.seconds();
    if (tty_)
        fmt::print(stderr, "\r{}\x1b[K", line(done, rays));
    else
        fmt::print(stderr, "{}\n", line(done, rays));
    std::fflush(stderr);
    printed_ = true;
}

void Progress::finish(int done, std::uint64_t rays) {
    if (!enabled_) return;
    if (tty_)
        fmt::print(stderr, "\r{}\x1b[K\n", line(done, rays));
    else
        fmt::print(stderr, "{}\n", line(done, rays));
    std::fflush(stderr);
}

}  // namespace wp::render
