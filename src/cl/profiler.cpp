#include "cl/profiler.h"

#include <algorithm>

namespace wp::ocl {

void Profiler::begin_wave(double passes) {
    // The open wave closes when resolve() reaches this marker, after its own launches.
    pending_.push_back({std::string(), ::cl::Event(), wave_count_, passes, true});
    passes_total_ += passes;
    ++wave_count_;
}

void Profiler::add(const std::string& name, const ::cl::Event& ev) {
    pending_.push_back({name, ev, wave_count_ - 1, 0.0, false});
}

std::size_t Profiler::stage_index(const std::string& name) {
    for (std::size_t i = 0; i < stages_.size(); ++i)
        if (stages_[i].name == name) return i;
    stages_.push_back({name});
    return stages_.size() - 1;
}

WaveRecord Profiler::finished(const OpenWave& w) const {
    WaveRecord r = w.rec;
    r.span_ms = w.any ? (w.hi - w.lo) * 1e-6 : 0.0;
    return r;
}

void Profiler::close_wave() {
    if (!open_.any && open_.rec.passes == 0.0) return;
    for (std::size_t i = 0; i < open_.per_stage.size(); ++i)
        stages_[i].max_ms_per_wave = std::max(stages_[i].max_ms_per_wave, open_.per_stage[i]);
    span_ms_closed_ += finished(open_).span_ms;
    if (open_.rec.index % wave_stride_ == 0) waves_.push_back(finished(open_));
    if (waves_.size() >= kMaxWaves) {
        // Keep every other wave from now on (and of those kept so far).
        std::vector<WaveRecord> kept;
        for (std::size_t i = 0; i < waves_.size(); i += 2) kept.push_back(waves_[i]);
        waves_ = std::move(kept);
        wave_stride_ *= 2;
    }
    open_ = OpenWave();
}

void Profiler::resolve() {
    for (auto& p : pending_) {
        if (p.wave_start) {
            close_wave();
            open_.rec.index = p.wave;
            open_.rec.passes = p.passes;
            continue;
        }
        p.event.wait();
        LaunchRecord r;
        r.name = p.name;
        r.wave = p.wave;
        r.queued_ns = p.event.getProfilingInfo<CL_PROFILING_COMMAND_QUEUED>();
        r.start_ns = p.event.getProfilingInfo<CL_PROFILING_COMMAND_START>();
        r.end_ns = p.event.getProfilingInfo<CL_PROFILING_COMMAND_END>();
        double ms = (r.end_ns - r.start_ns) * 1e-6;
        std::size_t s = stage_index(r.name);
        stages_[s].launches += 1;
        stages_[s].total_ms += ms;
        stages_[s].max_ms = std::max(stages_[s].max_ms, ms);
        if (r.wave >= 0) {
            if (open_.per_stage.size() <= s) open_.per_stage.resize(s + 1, 0.0);
            open_.per_stage[s] += ms;
            open_.rec.kernel_ms += ms;
            open_.lo = std::min(open_.lo, r.start_ns);
            open_.hi = std::max(open_.hi, r.end_ns);
            open_.any = true;
        }
        if (trace_.size() < kMaxTrace)
            trace_.push_back(std::move(r));
        else
            ++trace_dropped_;
    }
    pending_.clear();
}

std::vector<StageTotals> Profiler::totals() const {
    std::vector<StageTotals> out = stages_;
    for (std::size_t i = 0; i < open_.per_stage.size(); ++i)
        out[i].max_ms_per_wave = std::max(out[i].max_ms_per_wave, open_.per_stage[i]);
    return out;
}

std::vector<WaveRecord> Profiler::waves() const {
    std::vector<WaveRecord> out = waves_;
    if (open_.any && open_.rec.index % wave_stride_ == 0) out.push_back(finished(open_));
    return out;
}

double Profiler::span_ms() const { return span_ms_closed_ + finished(open_).span_ms; }

void Profiler::clear() { *this = Profiler(); }

::cl::Event launch(const ::cl::CommandQueue& queue, const ::cl::Kernel& kernel, const std::string& name,
                   std::size_t count, Profiler* profiler, std::size_t local) {
    std::size_t global = (count + local - 1) / local * local;
    if (global == 0) global = local;
    ::cl::Event ev;
    queue.enqueueNDRangeKernel(kernel, ::cl::NullRange, ::cl::NDRange(global), ::cl::NDRange(local),
                               nullptr, &ev);
    if (profiler) profiler->add(name, ev);
    return ev;
}

}  // namespace wp::ocl
