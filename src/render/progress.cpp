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

std::string format_spp(double spp) {
    if (spp == static_cast<double>(static_cast<long long>(spp)))
        return fmt::format("{}", static_cast<long long>(spp));
    return fmt::format("{:.2f}", spp);
}

}  // namespace

Progress::Progress(int total_samples, double time_limit_s, bool enabled)
    : total_(total_samples), time_limit_s_(time_limit_s), enabled_(enabled),
      tty_(isatty(fileno(stderr)) != 0) {}

bool Progress::due() const {
    if (!enabled_) return false;
    return timer_.seconds() - last_print_s_ >= (tty_ ? 0.125 : 1.0);
}

void Progress::step(double spp, double seconds) {
    if (steps_seen_++ == 0) return;  // the first step includes the JIT
    recent_.emplace_back(spp, seconds);
    if (recent_.size() > kAverageSteps) recent_.pop_front();
}

std::string Progress::line(double done, std::uint64_t rays) const {
    double el = timer_.seconds();
    double eta = done > 0 ? el / done * (total_ - done) : 1e30;
    double avg_spp = 0.0, avg_s = 0.0;
    for (const auto& [spp, sec] : recent_) {
        avg_spp += spp;
        avg_s += sec;
    }
    if (avg_spp > 0.0) eta = avg_s / avg_spp * std::max(0.0, total_ - done);
    if (time_limit_s_ > 0.0) eta = std::min(eta, std::max(0.0, time_limit_s_ - el));
    double mrays = el > 0.0 ? rays / el * 1e-6 : 0.0;
    if (open_ended_)
        return fmt::format("render: {} spp  elapsed {}{}  {:.1f} Mrays/s{}{}", format_spp(done),
                           format_duration(el),
                           time_limit_s_ > 0.0 ? "  ETA " + format_duration(std::max(0.0, time_limit_s_ - el)) : "",
                           mrays, note_.empty() ? "" : "  ", note_);
    return fmt::format("render: {}/{} spp ({:3.0f}%)  elapsed {}  ETA {}  {:.1f} Mrays/s{}{}",
                       format_spp(done), total_, 100.0 * done / std::max(total_, 1), format_duration(el),
                       done > 0 || time_limit_s_ > 0.0 ? format_duration(eta) : "?", mrays,
                       note_.empty() ? "" : "  ", note_);
}

void Progress::update(double done, std::uint64_t rays) {
    if (!due()) return;
    last_print_s_ = timer_.seconds();
    if (tty_)
        fmt::print(stderr, "\r{}\x1b[K", line(done, rays));
    else
        fmt::print(stderr, "{}\n", line(done, rays));
    std::fflush(stderr);
    printed_ = true;
}

void Progress::finish(double done, std::uint64_t rays, bool interrupted) {
    if (!enabled_) return;
    std::string l = line(done, rays);
    if (interrupted) l += fmt::format("  (interrupted at {} spp)", format_spp(done));
    if (tty_)
        fmt::print(stderr, "\r{}\x1b[K\n", l);
    else
        fmt::print(stderr, "{}\n", l);
    std::fflush(stderr);
}

}  // namespace wp::render
