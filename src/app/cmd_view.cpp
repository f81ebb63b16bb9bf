// cmd_view.cpp — `wavepath view [SCENE]`: the interactive viewer (docs/viewer.md).
//
// One more client of the renderer: the same scene arguments and render options as `render`
// (app/render_options.h), one Wavefront whose film is shown as it accumulates. Each loop turn
// enqueues one more sample per pixel (Wavefront::render_passes(1)), waits for it, reads the
// resolved film (Wavefront::resolve), tone-maps it on the host (image/tonemap.h) into an
// RGBA8 texture and draws it 1:1 into the window (OpenGL 1.1 textured quad, nearest
// sampling). The navigation moves the scene's Camera (scene/camera_control.h), which reaches
// the generate stage through Wavefront::set_camera and restarts the film; a resize makes a
// new Wavefront at the window's framebuffer size.
//
// The window part (GLFW + OpenGL) is an optional CMake component (WP_HAVE_VIEWER); without it
// `view` says so and exits 1. Without a display ($DISPLAY and $WAYLAND_DISPLAY unset, or
// glfwInit failing) it says so, suggests `render`, and exits 1 before any work.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "app/render_options.h"
#include "app/subcommands.h"
#include "image/codec.h"
#include "image/image.h"
#include "image/tonemap.h"
#include "scene/camera_control.h"
#include "util/error.h"
#include "util/limits.h"

#ifdef WP_HAVE_VIEWER

#define GLFW_INCLUDE_NONE
#include <GL/gl.h>
#include <GLFW/glfw3.h>

#include "cl/device.h"
#include "render/aov.h"
#include "render/denoise.h"
#include "render/film.h"
#include "render/profile.h"
#include "render/wavefront.h"
#include "util/atomic_file.h"
#include "util/timer.h"
#endif

namespace wp::app {

namespace fs = std::filesystem;

namespace {

struct ViewArgs {
    std::string scene;
    int spp = limits::kMaxSpp;  // accumulation stops here (the viewer keeps showing)
    ConfigArgs config;
    SceneEdits edits;
    long long seed = 0;
    bool seed_given = false;
    std::string output = "view";  // the save key writes OUTPUT.exr, .png, .camera.json
    double exposure = 0.0;
    std::string tonemap = "clamp";
    bool no_srgb = false;
    int frames = 0;          // > 0: quit after this many samples per pixel were shown
    std::string screenshot;  // with --frames: the window's pixels as PNG at the end
    bool quiet = false;
    bool no_show = false;    // measuring: render without reading back or drawing
    bool views = false;      // --views: also keep AOVs and variance (V cycles the views)
    std::string view = "color";
};

// What the window shows (V cycles them with --views). Every view but color reads the film
// blocking (no double buffering); denoised runs the denoise stage (docs/denoise.md) on the
// current film, as `render --denoise` does.
enum class View { Color, Albedo, Normal, Depth, Variance, Denoised };
constexpr const char* kViewNames[] = {"color", "albedo", "normal", "depth", "variance", "denoised"};
constexpr int kViewCount = 6;

std::optional<View> parse_view(const std::string& name) {
    for (int i = 0; i < kViewCount; ++i)
        if (name == kViewNames[i]) return static_cast<View>(i);
    return std::nullopt;
}

bool have_display() {
    const char* x = std::getenv("DISPLAY");
    const char* w = std::getenv("WAYLAND_DISPLAY");
    return (x && *x) || (w && *w);
}

constexpr const char* kNoDisplay =
    "no display to open a window on ($DISPLAY and $WAYLAND_DISPLAY are unset{}); use "
    "`wavepath render` to render the scene to an image file instead";

#ifdef WP_HAVE_VIEWER

// What the callbacks collect between two loop turns.
struct Input {
    double last_x = 0.0, last_y = 0.0;
    bool have_last = false;
    double orbit_x = 0.0, orbit_y = 0.0;  // pixels dragged with the left button
    double pan_x = 0.0, pan_y = 0.0;      // right or middle button
    double scroll = 0.0;
    bool reset = false, pause = false, save = false, camera_save = false;
    int exposure_steps = 0;
    bool next_curve = false, toggle_srgb = false, next_view = false;
    bool resized = false;
};

void on_key(GLFWwindow* w, int key, int, int action, int) {
    if (action != GLFW_PRESS) return;
    auto* in = static_cast<Input*>(glfwGetWindowUserPointer(w));
    switch (key) {
        case GLFW_KEY_R: in->reset = true; break;
        case GLFW_KEY_SPACE: in->pause = true; break;
        case GLFW_KEY_P: in->save = true; break;
        case GLFW_KEY_C: in->camera_save = true; break;
        case GLFW_KEY_EQUAL: case GLFW_KEY_KP_ADD: ++in->exposure_steps; break;
        case GLFW_KEY_MINUS: case GLFW_KEY_KP_SUBTRACT: --in->exposure_steps; break;
        case GLFW_KEY_T: in->next_curve = true; break;
        case GLFW_KEY_G: in->toggle_srgb = true; break;
        case GLFW_KEY_V: in->next_view = true; break;
        case GLFW_KEY_ESCAPE: case GLFW_KEY_Q: glfwSetWindowShouldClose(w, GLFW_TRUE); break;
        default: break;
    }
}

void on_cursor(GLFWwindow* w, double x, double y) {
    auto* in = static_cast<Input*>(glfwGetWindowUserPointer(w));
    if (in->have_last) {
        const double dx = x - in->last_x, dy = y - in->last_y;
        if (glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS) {
            in->orbit_x += dx;
            in->orbit_y += dy;
        } else if (glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS ||
                   glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS) {
            in->pan_x += dx;
            in->pan_y += dy;
        }
    }
    in->last_x = x;
    in->last_y = y;
    in->have_last = true;
}

void on_scroll(GLFWwindow* w, double, double dy) {
    static_cast<Input*>(glfwGetWindowUserPointer(w))->scroll += dy;
}

void on_resize(GLFWwindow* w, int, int) {
    static_cast<Input*>(glfwGetWindowUserPointer(w))->resized = true;
}

// The window's back buffer (what was just drawn) as an 8-bit PNG, written atomically.
void write_screenshot(const fs::path& path, int w, int h) {
    std::vector<std::uint8_t> px(static_cast<std::size_t>(w) * h * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, px.data());
    std::vector<std::uint8_t> rgb(static_cast<std::size_t>(w) * h * 3);
    for (int y = 0; y < h; ++y)  // OpenGL's rows go bottom-up
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c)
                rgb[(static_cast<std::size_t>(y) * w + x) * 3 + c] =
                    px[(static_cast<std::size_t>(h - 1 - y) * w + x) * 4 + c];
    write_atomically(path, [&](const fs::path& tmp) {
        codec::WriteSpec spec;
        spec.width = w;
        spec.height = h;
        spec.channel_names = {"R", "G", "B"};
        spec.type = codec::Pixel::UInt8;
        spec.attributes = {{"oiio:ColorSpace", "sRGB"}};
        std::string why;
        if (!codec::image_codec().write(tmp.string(), "png", spec, rgb.data(), &why))
            fail("{}: cannot write the screenshot: {}", path.string(), why);
    });
}

struct Glfw {
    ~Glfw() { glfwTerminate(); }
};

// The image of a view other than color, from the current film (blocking). variance: the
// standard error sqrt(s^2 / n) per channel.
Image view_image(render::Wavefront& wf, View v, std::unique_ptr<render::Denoiser>& dn) {
    switch (v) {
        case View::Albedo: return wf.aovs().albedo;
        case View::Normal: return render::aov_preview_normal(wf.aovs());
        case View::Depth: return render::aov_preview_depth(wf.aovs());
        case View::Variance: {
            Image img = wf.moments().mean_variance;
            for (float& x : img.rgb) x = std::sqrt(std::max(x, 0.0f));
            return img;
        }
        case View::Denoised: {
            if (!dn) dn = std::make_unique<render::Denoiser>(wf.device());
            render::FilmMoments m = wf.moments();
            return dn->run(m.mean, m.mean_variance, wf.aovs());
        }
        case View::Color: break;
    }
    return wf.resolve();
}

int run_view_window(const ViewArgs& a, ToneMapping tone, View view) {
    glfwSetErrorCallback([](int, const char*) {});  // glfwInit's failure is reported below
    if (!glfwInit()) {
        const char* why = nullptr;
        glfwGetError(&why);
        fail(kNoDisplay, fmt::format("; GLFW: {}", why ? why : "glfwInit failed"));
    }
    Glfw glfw_guard;

    // Scene, settings and device, as `render` makes them.
    Scene scene = load_scene(a.scene, a.quiet, &a.edits);
    render::RenderSettings s = make_settings(a.config, scene);
    s.seed = a.seed_given || !scene.render.seed ? static_cast<std::uint32_t>(a.seed) : *scene.render.seed;
    if (a.views) s.aov = s.variance = true;  // the AOV, variance and denoised views
    std::unique_ptr<render::Denoiser> denoiser;
    ocl::Device dev = ocl::Device::open(a.config.device);
    Camera camera = scene.camera;
    camera.width = s.width;
    camera.height = s.height;

    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 2);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 1);
    GLFWwindow* win = glfwCreateWindow(s.width, s.height, "wavepath view", nullptr, nullptr);
    if (!win) {
        const char* why = nullptr;
        glfwGetError(&why);
        fail("cannot open a {}x{} OpenGL window: {}; use `wavepath render` instead", s.width,
             s.height, why ? why : "unknown GLFW error");
    }
    Input input;
    glfwSetWindowUserPointer(win, &input);
    glfwSetKeyCallback(win, on_key);
    glfwSetCursorPosCallback(win, on_cursor);
    glfwSetScrollCallback(win, on_scroll);
    glfwSetFramebufferSizeCallback(win, on_resize);
    glfwMakeContextCurrent(win);
    glfwSwapInterval(0);  // the renderer sets the pace, not the monitor

    GLuint tex = 0;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP);
    glEnable(GL_TEXTURE_2D);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);

    // The film follows the framebuffer (which may differ from the requested size).
    int fb_w = 0, fb_h = 0;
    glfwGetFramebufferSize(win, &fb_w, &fb_h);
    std::unique_ptr<render::Wavefront> wf;
    int tex_w = 0, tex_h = 0;
    auto rebuild = [&](int w, int h) {
        dev.queue.finish();  // reads in flight into the snapshots
        wf.reset();
        s.width = std::max(w, 1);
        s.height = std::max(h, 1);
        camera.width = s.width;
        camera.height = s.height;
        scene.camera = camera;
        wf = std::make_unique<render::Wavefront>(dev, scene, s);
        glViewport(0, 0, s.width, s.height);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, s.width, s.height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
        tex_w = s.width;
        tex_h = s.height;
    };
    rebuild(fb_w, fb_h);
    if (!a.quiet)
        for (const auto& w : wf->scene_warnings()) fmt::print(stderr, "wavepath: warning: {}\n", w);

    bool paused = false;
    bool dirty = true;       // the shown image's display settings changed
    bool need_read = true;   // the shown image is out of date and no read is in flight
    // Two host buffers of the raw film, filled by non-blocking reads (double buffering);
    // adaptive sampling resolves with per-pixel counts, so it reads the film blocking.
    struct Snapshot {
        std::vector<FilmPixel> film;
        ::cl::Event done;
        int samples = 0;
        bool pending = false;
        cl_ulong rays[2] = {0, 0};  // ray totals read along
    };
    Snapshot snaps[2];
    int next_snap = 0;
    const bool use_snapshots = !s.adaptive.enabled;
    int shown_spp = 0;
    double turn_ms = 0.0;    // wall time of the previous loop turn
    ::cl::Event no_show_marker;  // --no-show: the end of the previous pass
    std::vector<std::uint8_t> rgba;
    Image shown;        // the latest resolved film (saved by P)
    // Live numbers since the last restart, and the display's cost.
    double render_ms_last = 0.0, display_ms_last = 0.0;
    double render_ms_sum = 0.0, display_ms_sum = 0.0;
    double read_ms_sum = 0.0, tone_ms_sum = 0.0;  // parts of display_ms_sum (the rest: GL)
    int displayed = 0;        // frames shown while rendering (display sums)
    int frames_timed = 0;     // turns that rendered after a turn that rendered (render_ms_sum)
    int skipped = 0;          // passes not shown (the display's share, below)
    bool rendered_before = false;
    double since_shown_ms = 0.0;
    Timer since_start;  // wall time since the last restart (Mrays/s)
    std::uint64_t rays = 0;
    Timer title_timer, profile_timer;
    std::string split;  // the per-stage split of the device time, for the title
    double last_turn_s = 0.0;
    Timer turn_timer;
    auto restart = [&] {  // after the film was cleared (the queue has drained)
        render_ms_sum = display_ms_sum = read_ms_sum = tone_ms_sum = 0.0;
        displayed = frames_timed = skipped = 0;
        render_ms_last = 0.0;
        rendered_before = false;
        since_shown_ms = 0.0;
        since_start.reset();
        snaps[0].pending = snaps[1].pending = false;  // reads of the old film
        need_read = true;
    };

    while (!glfwWindowShouldClose(win)) {
        last_turn_s = turn_timer.seconds();
        turn_ms = last_turn_s * 1e3;
        turn_timer.reset();
        glfwPollEvents();

        // Input: display changes redraw; camera changes restart the film.
        if (input.resized) {
            input.resized = false;
            glfwGetFramebufferSize(win, &fb_w, &fb_h);
            if (fb_w > 0 && fb_h > 0 && (fb_w != s.width || fb_h != s.height)) {
                rebuild(fb_w, fb_h);
                restart();
            }
        }
        if (input.exposure_steps != 0) {
            tone.exposure = std::clamp(tone.exposure + input.exposure_steps * limits::kViewerExposureStep,
                                       -limits::kViewerMaxExposure, limits::kViewerMaxExposure);
            input.exposure_steps = 0;
            dirty = true;
        }
        if (input.next_curve) tone.curve = next_tone_curve(tone.curve), input.next_curve = false, dirty = true;
        if (input.toggle_srgb) tone.srgb = !tone.srgb, input.toggle_srgb = false, dirty = true;
        if (input.pause) paused = !paused, input.pause = false;
        if (input.next_view) {
            input.next_view = false;
            if (a.views) {
                view = static_cast<View>((static_cast<int>(view) + 1) % kViewCount);
                need_read = true;
            }
        }
        Camera moved = camera;
        if (input.orbit_x != 0.0 || input.orbit_y != 0.0)
            moved = orbit_camera(moved, float(-input.orbit_x * limits::kViewerOrbitRadPerPixel),
                                 float(input.orbit_y * limits::kViewerOrbitRadPerPixel));
        if (input.pan_x != 0.0 || input.pan_y != 0.0) {
            // One pixel at the target is 2 tan(fov/2) / height distances.
            const double per_px = 2.0 * std::tan(glm::radians(camera.vfov_deg) * 0.5) / s.height;
            moved = pan_camera(moved, float(-input.pan_x * per_px), float(input.pan_y * per_px));
        }
        if (input.scroll != 0.0)
            moved = dolly_camera(moved, float(std::pow(limits::kViewerDollyPerScroll, input.scroll)));
        input.orbit_x = input.orbit_y = input.pan_x = input.pan_y = input.scroll = 0.0;
        {
            const float step = float(limits::kViewerFlySpeed * std::min(last_turn_s, 0.25) *
                                     glm::length(camera.target - camera.position));
            float fr = 0.0f, ff = 0.0f;
            if (glfwGetKey(win, GLFW_KEY_W) == GLFW_PRESS) ff += step;
            if (glfwGetKey(win, GLFW_KEY_S) == GLFW_PRESS) ff -= step;
            if (glfwGetKey(win, GLFW_KEY_D) == GLFW_PRESS) fr += step;
            if (glfwGetKey(win, GLFW_KEY_A) == GLFW_PRESS) fr -= step;
            if (fr != 0.0f || ff != 0.0f) moved = fly_camera(moved, fr, 0.0f, ff);
        }
        if (moved.position != camera.position || moved.target != camera.target) {
            try {
                wf->set_camera(moved);
                camera = moved;
            } catch (const Error&) {
                // A degenerate camera (e.g. dollied onto its target): keep the old one.
            }
            restart();
        }
        if (input.reset) {
            input.reset = false;
            wf->reset(s.seed);
            restart();
        }

        // One more sample per pixel, unless paused or done, and (double buffering) a
        // non-blocking read of the film behind it into one of two host buffers: the queue
        // runs them in order, so the read sees exactly that pass.
        const bool rendering = !paused && wf->frames() < a.spp && (a.frames == 0 || wf->frames() < a.frames);
        if (rendering) {
            // The previous turn's wall time is one pass's (while the one before was shown).
            if (rendered_before) {
                render_ms_last = turn_ms;
                render_ms_sum += turn_ms;
                ++frames_timed;
                since_shown_ms += turn_ms;
            }
            wf->render_passes(1);
            if (a.no_show) {
                // The same pipelining without the display: wait for the pass before this one.
                ::cl::Event marker;
                dev.queue.enqueueMarkerWithWaitList(nullptr, &marker);
                if (no_show_marker()) no_show_marker.wait();
                no_show_marker = marker;
                shown_spp = wf->frames() - 1;
            } else if (use_snapshots) {
                Snapshot& sn = snaps[next_snap];
                sn.done = wf->enqueue_film_read(sn.film, sn.rays);
                sn.samples = wf->frames();
                sn.pending = true;
                next_snap ^= 1;
            } else {
                dev.queue.finish();
                need_read = true;
            }
        }

        rendered_before = rendering;
        if (a.no_show && !rendering) {
            dev.queue.finish();
            shown_spp = wf->frames();
        }

        // Show the previous pass (its read was enqueued before this turn's pass, which runs
        // on the device meanwhile): resolve, tone-map, upload, draw. Display changes redraw
        // what is shown; a restart that left nothing in flight reads the film directly.
        Snapshot& prev = snaps[next_snap];  // the older of the two
        Snapshot& newest = snaps[next_snap ^ 1];
        Snapshot* ready = prev.pending ? &prev : (!rendering && newest.pending) ? &newest : nullptr;
        if (ready && rendering && !need_read && !dirty) {
            // The display's share of the renderer's time stays <= kViewerDisplayShare: a pass
            // is shown once the passes since the last shown one took (1/share - 1) times the
            // display's cost; the others are skipped (their read is cheap and paces the loop).
            ready->done.wait();
            if (since_shown_ms < display_ms_last * (1.0 / limits::kViewerDisplayShare - 1.0)) {
                ready->pending = false;
                ready = nullptr;
                ++skipped;
            }
        }
        if (!a.no_show && (ready || need_read || dirty)) {
            Timer t;
            if (view != View::Color && (ready || need_read)) {
                // The other views read the current film (blocking): its passes so far.
                if (ready) ready->done.wait(), ready->pending = false;
                rays = ready ? ready->rays[0] + ready->rays[1] : rays;
                ready = nullptr;
                dev.queue.finish();
                shown = view_image(*wf, view, denoiser);
                shown_spp = wf->frames();
            } else if (ready) {
                ready->done.wait();
                render::resolve_film_into(ready->film.data(), ready->film.size(), 0, ready->samples, shown);
                shown_spp = ready->samples;
                rays = ready->rays[0] + ready->rays[1];
                ready->pending = false;
            } else if (need_read) {
                shown = wf->resolve();
                shown_spp = wf->frames();
            }
            need_read = false;
            const double read_ms = t.ms();
            tonemap_rgba8(shown, tone, rgba);
            const double tone_ms = t.ms() - read_ms;
            glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, tex_w, tex_h, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
            glMatrixMode(GL_PROJECTION);
            glLoadIdentity();
            glOrtho(0, 1, 0, 1, -1, 1);
            glMatrixMode(GL_MODELVIEW);
            glLoadIdentity();
            glBegin(GL_QUADS);  // texture row 0 is the image's top row
            glTexCoord2f(0, 1); glVertex2f(0, 0);
            glTexCoord2f(1, 1); glVertex2f(1, 0);
            glTexCoord2f(1, 0); glVertex2f(1, 1);
            glTexCoord2f(0, 0); glVertex2f(0, 1);
            glEnd();
            glFinish();
            // A blocking read also waited for the device: not the display's cost.
            display_ms_last = ready ? t.ms() : t.ms() - read_ms;
            // Steady state only: a pass rendered in this turn and the one before.
            if (rendering && ready) {
                display_ms_sum += display_ms_last;
                read_ms_sum += read_ms;
                tone_ms_sum += tone_ms;
                ++displayed;
            }
            since_shown_ms = 0.0;
            dirty = false;
        }

        // --frames: the end of a scripted run (the screenshot is the window's back buffer).
        if (a.frames > 0 && shown_spp >= a.frames) {
            if (!a.screenshot.empty()) write_screenshot(a.screenshot, tex_w, tex_h);
            glfwSwapBuffers(win);
            break;
        }
        if (input.save || input.camera_save) {
            if (input.save) {
                std::vector<ImageAttribute> attrs = {{"wavepath:spp", std::to_string(shown_spp), true}};
                write_image(a.output + ".exr", shown, attrs);
                write_image(a.output + ".png", apply_tone_mapping(shown, tone), attrs);
            }
            write_text_atomically(a.output + ".camera.json", camera_json_snippet(camera));
            if (!a.quiet)
                fmt::print("saved {}{}.camera.json at {} spp\n",
                           input.save ? fmt::format("{0}.exr, {0}.png, ", a.output) : std::string(),
                           a.output, shown_spp);
            input.save = input.camera_save = false;
        }
        glfwSwapBuffers(win);

        // Live numbers in the title, twice a second (the ray total is an 8-byte read).
        if (title_timer.seconds() >= limits::kViewerTitleInterval_s) {
            title_timer.reset();
            if (!use_snapshots) rays = wf->rays_traced();
            const double secs = std::max(since_start.seconds(), 1e-9);
            // The per-stage split waits for the launches in flight: refreshed less often.
            if (profile_timer.seconds() >= limits::kViewerProfileInterval_s || split.empty()) {
                profile_timer.reset();
                wf->profiler().resolve();
                render::ProfileSummary p = render::summarize_profile(wf->profiler(), rays);
                split.clear();
                for (const auto& st : p.stages)
                    if (st.percent >= 1.0) split += fmt::format(" {} {:.0f}%", st.name, st.percent);
            }
            const double frame_ms = frames_timed ? render_ms_sum / frames_timed : render_ms_last;
            const double disp_ms = displayed ? display_ms_sum / displayed : display_ms_last;
            const double share = render_ms_sum > 0.0 ? display_ms_sum / render_ms_sum : 0.0;
            std::string title = fmt::format(
                "wavepath view | {} spp{} | {:.1f} ms/frame | {:.2f} Mrays/s | display {:.2f} ms "
                "({:.1f}%) |{} | {}{} exp {:+.1f}{}",
                shown_spp, paused ? " (paused)" : "", frame_ms, double(rays) / secs * 1e-6,
                disp_ms, 100.0 * share, split,
                view == View::Color ? "" : fmt::format("{} view, ", kViewNames[int(view)]),
                tone_curve_name(tone.curve), tone.exposure, tone.srgb ? "" : " linear");
            glfwSetWindowTitle(win, title.c_str());
        }
        if (!rendering && !dirty && !snaps[0].pending && !snaps[1].pending)
            glfwWaitEventsTimeout(0.05);  // idle: no busy loop
    }
    if (!a.quiet && frames_timed > 0 && a.no_show) {
        fmt::print("{}x{}: {} spp; {:.2f} ms per frame rendering, nothing shown (--no-show)\n",
                   s.width, s.height, wf->frames(), render_ms_sum / frames_timed);
    } else if (!a.quiet && frames_timed > 0 && displayed > 0) {
        const double frame_ms = render_ms_sum / frames_timed, disp_ms = display_ms_sum / displayed;
        fmt::print("{}x{}: {} spp; {:.2f} ms per frame rendering; {} of {} passes shown, {:.2f} ms "
                   "each = {:.2f}% of the render time (read-back {:.2f}, tone map {:.2f}, upload "
                   "and draw {:.2f} ms)\n",
                   s.width, s.height, wf->frames(), frame_ms, displayed, displayed + skipped, disp_ms,
                   100.0 * display_ms_sum / render_ms_sum,
                   read_ms_sum / displayed, tone_ms_sum / displayed,
                   (display_ms_sum - read_ms_sum - tone_ms_sum) / displayed);
    }
    glDeleteTextures(1, &tex);
    glfwDestroyWindow(win);
    return 0;
}

#endif  // WP_HAVE_VIEWER

int run_view(const ViewArgs& a) {
    // Options first (usage errors, exit 2), then the display (exit 1), then any work.
    if (a.spp < limits::kMinSpp || a.spp > limits::kMaxSpp)
        usage_fail("--spp must be in {}..{} (got {})", limits::kMinSpp, limits::kMaxSpp, a.spp);
    if (a.seed < 0 || a.seed > limits::kMaxSeed)
        usage_fail("--seed must be in 0..{} (got {})", limits::kMaxSeed, a.seed);
    if (a.frames < 0 || a.frames > limits::kViewerMaxFrames)
        usage_fail("--frames must be in 0..{} (got {})", limits::kViewerMaxFrames, a.frames);
    if (!a.screenshot.empty() && a.frames == 0) usage_fail("--screenshot needs --frames N");
    if (a.no_show && !a.screenshot.empty()) usage_fail("--screenshot shows nothing with --no-show");
    if (a.frames > a.spp) usage_fail("--frames ({}) must not exceed --spp ({})", a.frames, a.spp);
    if (!(std::fabs(a.exposure) <= limits::kViewerMaxExposure))
        usage_fail("--exposure must be in -{0}..{0} stops (got {1})", limits::kViewerMaxExposure, a.exposure);
    const auto curve = parse_tone_curve(a.tonemap);
    if (!curve) usage_fail("--tonemap must be clamp, reinhard or filmic (got '{}')", a.tonemap);
    const auto view = parse_view(a.view);
    if (!view)
        usage_fail("--view must be color, albedo, normal, depth, variance or denoised (got '{}')", a.view);
    if (*view != View::Color && !a.views)
        usage_fail("--view {} needs --views (which keeps the AOVs and the variance)", a.view);
    if (a.views && a.config.adaptive)
        usage_fail("--views cannot be combined with --adaptive yet (the feature buffers follow the "
                   "plain wave layout only)");
    check_scene_edits(a.edits);
    if (!a.screenshot.empty()) {
        if (fs::path(a.screenshot).extension() != ".png")
            usage_fail("--screenshot must name a .png file (got '{}')", a.screenshot);
        check_writable(a.screenshot, "--screenshot", true);
    }
#ifndef WP_HAVE_VIEWER
    fail("this wavepath was built without the viewer (configured with WP_WITH_VIEWER=OFF, or "
         "without GLFW 3 and OpenGL: Debian libglfw3-dev, libgl-dev); use `wavepath render` instead");
#else
    if (!have_display()) fail(kNoDisplay, "");
    ToneMapping tone;
    tone.exposure = a.exposure;
    tone.curve = *curve;
    tone.srgb = !a.no_srgb;
    return run_view_window(a, tone, *view);
#endif
}

}  // namespace

Subcommand add_view(CLI::App& app) {
    auto args = std::make_shared<ViewArgs>();
    Subcommand s;
    s.app = app.add_subcommand(
        "view",
        "Show a scene in a window while it converges (docs/viewer.md): the progressive film, "
        "mouse and WASD navigation (restarts accumulation), and live numbers in the title. "
        "Keys: left drag orbit, right/middle drag pan, wheel dolly, W/A/S/D fly, R reset, "
        "Space pause, P save OUTPUT.exr/.png/.camera.json, C save the camera only, +/- "
        "exposure, T tone curve, G sRGB on/off, V next view (with --views), Q/Esc quit. Needs a display ($DISPLAY or "
        "$WAYLAND_DISPLAY); without one it exits 1 (use `render`).");
    auto* c = s.app;
    c->add_option("scene", args->scene, kSceneArgHelp);
    c->add_option("--spp", args->spp,
                  "Stop accumulating at this many samples per pixel (the window stays open); "
                  "default: no limit (2^24)")
        ->capture_default_str();
    add_config_options(c, args->config);
    add_scene_edit_options(c, args->edits);
    c->add_option("--seed", args->seed,
                  "Random seed (beats the scene file's): the same seed gives `render`'s image")
        ->capture_default_str()
        ->each([a = args.get()](const std::string&) { a->seed_given = true; });
    c->add_option("-o,--output", args->output,
                  "Base name of what the P and C keys save: BASE.exr (the linear film), BASE.png "
                  "(after exposure and tone curve, sRGB), BASE.camera.json (the camera as a JSON "
                  "scene snippet)")
        ->capture_default_str();
    c->add_option("--exposure", args->exposure, "Exposure in stops (display and saved PNG)")
        ->capture_default_str();
    c->add_option("--tonemap", args->tonemap,
                  "Tone curve: clamp, reinhard (x/(1+x)) or filmic (ACES-like fit)")
        ->capture_default_str();
    c->add_flag("--no-srgb", args->no_srgb, "Show linear codes instead of sRGB-encoded ones");
    c->add_option("--frames", args->frames,
                  "Quit after this many samples per pixel were shown (scripted runs, tests); "
                  "0 = run until closed")
        ->capture_default_str();
    c->add_option("--screenshot", args->screenshot,
                  "With --frames: write the window's pixels (read back from its framebuffer) "
                  "as this PNG at the end");
    c->add_flag("--views", args->views,
                "Also keep the feature buffers (albedo, normal, depth) and the variance, so that V "
                "cycles the views color, albedo, normal, depth, variance (standard error) and "
                "denoised (the denoise stage on the current film); costs what render --aov and "
                "--variance cost, and the views other than color read the film blocking");
    c->add_option("--view", args->view,
                  "The view shown first: color, or with --views albedo, normal, depth, variance, "
                  "denoised")
        ->capture_default_str();
    c->add_flag("-q,--quiet", args->quiet, "No scene report, warnings or summary line");
    c->add_flag("--no-show", args->no_show,
                "Measuring: render the passes the same way without reading back, tone mapping "
                "or drawing them (the window stays black); with --frames its summary line is "
                "the baseline frame time of the display's cost (docs/viewer.md)");
    s.run = [args]() -> int { return run_view(*args); };
    return s;
}

}  // namespace wp::app
