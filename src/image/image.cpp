#include "image/image.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <system_error>

#include "image/codec.h"
#include "util/atomic_file.h"
#include "util/error.h"
#include "util/strings.h"

namespace wp {

namespace fs = std::filesystem;

namespace {

enum class Format { exr, png, jpeg, unknown };

Format format_of(const fs::path& path) {
    const std::string ext = ascii_lower(path.extension().string());
    if (ext == ".exr") return Format::exr;
    if (ext == ".png") return Format::png;
    if (ext == ".jpg" || ext == ".jpeg") return Format::jpeg;
    return Format::unknown;
}

std::size_t pixel_count(int w, int h) { return static_cast<std::size_t>(w) * h; }

// Writes `data` to `tmp` through the codec (the format from tmp's extension); `path` names
// the destination in messages.
void write_with_codec(const fs::path& path, const fs::path& tmp, const codec::WriteSpec& spec,
                      const void* data) {
    std::string why;
    if (!codec::image_codec().write(tmp.string(), "", spec, data, &why))
        fail("cannot write '{}': {}", path.string(), why);
}

// A reader of `path`; `what` words the failure ("cannot read 'F'" or "cannot read image 'F'").
std::unique_ptr<codec::Reader> open_reader(const fs::path& path, const char* what) {
    std::string why;
    std::unique_ptr<codec::Reader> in = codec::image_codec().open_file(path.string(), false, &why);
    if (!in) fail("{} '{}': {}", what, path.string(), why);
    return in;
}

codec::WriteSpec float_spec(int w, int h, std::vector<std::string> names) {
    codec::WriteSpec spec;
    spec.width = w;
    spec.height = h;
    spec.channel_names = std::move(names);
    spec.type = codec::Pixel::Float;
    spec.attributes = {{"oiio:ColorSpace", "Linear"}, {"compression", "zip"}};
    return spec;
}

void check_size(const fs::path& path, int w, int h, std::size_t floats) {
    if (w <= 0 || h <= 0) fail("cannot write '{}': image size {}x{} is empty", path.string(), w, h);
    if (floats != pixel_count(w, h) * 3)
        fail("cannot write '{}': {}x{} image holds {} floats, expected {}", path.string(), w, h,
             floats, pixel_count(w, h) * 3);
}

// Linear float → 8-bit sRGB code: clamp to [0, 1] (NaN → 0), encode, round to nearest.
std::uint8_t srgb_code(float linear) {
    double x = std::isnan(linear) ? 0.0 : std::clamp(static_cast<double>(linear), 0.0, 1.0);
    return static_cast<std::uint8_t>(std::floor(srgb_encode(x) * 255.0 + 0.5));
}

}  // namespace

double srgb_encode(double linear) {
    if (linear < 0.0031308) return 12.92 * linear;
    return 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

double srgb_decode(double encoded) {
    if (encoded < 12.92 * 0.0031308) return encoded / 12.92;
    return std::pow((encoded + 0.055) / 1.055, 2.4);
}

bool is_supported_image_path(const fs::path& path) { return format_of(path) != Format::unknown; }

namespace {

void add_attributes(codec::WriteSpec& spec, const std::vector<ImageAttribute>& attributes) {
    spec.attributes.insert(spec.attributes.end(), attributes.begin(), attributes.end());
}

}  // namespace

std::optional<std::string> read_image_attribute(const fs::path& path, const std::string& name) {
    return open_reader(path, "cannot read")->attribute(name);
}

void write_image(const fs::path& path, const Image& image,
                 const std::vector<ImageAttribute>& attributes) {
    Format format = format_of(path);
    if (format == Format::unknown)
        fail("cannot write '{}': unknown image extension '{}' (supported: .exr, .png, .jpg, .jpeg)",
             path.string(), path.extension().string());
    check_size(path, image.width, image.height, image.rgb.size());
    // libjpeg ends the process (exit) on larger images instead of reporting an error.
    if (format == Format::jpeg && (image.width > 65500 || image.height > 65500))
        fail("cannot write '{}': {}x{} is larger than JPEG allows (65500 pixels a side)",
             path.string(), image.width, image.height);

    write_atomically(path, [&](const fs::path& tmp) {
        if (format == Format::exr) {
            codec::WriteSpec spec = float_spec(image.width, image.height, {"R", "G", "B"});
            add_attributes(spec, attributes);
            write_with_codec(path, tmp, spec, image.rgb.data());
            return;
        }
        std::vector<std::uint8_t> codes(image.rgb.size());
        std::transform(image.rgb.begin(), image.rgb.end(), codes.begin(), srgb_code);
        codec::WriteSpec spec;
        spec.width = image.width;
        spec.height = image.height;
        spec.channel_names = {"R", "G", "B"};
        spec.type = codec::Pixel::UInt8;
        spec.attributes = {{"oiio:ColorSpace", "sRGB"}};
        add_attributes(spec, attributes);
        if (format == Format::jpeg) spec.attributes.push_back({"Compression", "jpeg:95"});
        write_with_codec(path, tmp, spec, codes.data());
    });
}

void write_exr_layers(const fs::path& path, int w, int h,
                      const std::vector<std::pair<std::string, const float*>>& rgb_layers) {
    if (format_of(path) != Format::exr)
        fail("cannot write '{}': layered images must be .exr", path.string());
    if (rgb_layers.empty()) fail("cannot write '{}': no layers given", path.string());
    check_size(path, w, h, pixel_count(w, h) * 3);

    // Interleave the layers: per pixel, every layer's R, G, B in turn.
    int nlayers = static_cast<int>(rgb_layers.size());
    std::vector<std::string> names;
    for (const auto& [name, data] : rgb_layers) {
        if (!data) fail("cannot write '{}': layer '{}' has no data", path.string(), name);
        std::string prefix = name.empty() ? std::string() : name + ".";
        for (const char* c : {"R", "G", "B"}) names.push_back(prefix + c);
    }
    std::vector<float> interleaved(pixel_count(w, h) * 3 * nlayers);
    for (std::size_t p = 0; p < pixel_count(w, h); ++p)
        for (int l = 0; l < nlayers; ++l)
            for (int c = 0; c < 3; ++c)
                interleaved[(p * nlayers + l) * 3 + c] = rgb_layers[l].second[p * 3 + c];

    write_atomically(path, [&](const fs::path& tmp) {
        write_with_codec(path, tmp, float_spec(w, h, names), interleaved.data());
    });
}

void write_exr_channels(const fs::path& path, int w, int h, const std::vector<ImageChannel>& channels,
                        const std::vector<ImageAttribute>& attributes) {
    if (format_of(path) != Format::exr)
        fail("cannot write '{}': images with named channels must be .exr", path.string());
    if (channels.empty()) fail("cannot write '{}': no channels given", path.string());
    if (w <= 0 || h <= 0) fail("cannot write '{}': image size {}x{} is empty", path.string(), w, h);
    std::vector<std::string> names;
    for (const auto& c : channels) {
        if (!c.data) fail("cannot write '{}': channel '{}' has no data", path.string(), c.name);
        if (std::find(names.begin(), names.end(), c.name) != names.end())
            fail("cannot write '{}': channel '{}' given twice", path.string(), c.name);
        names.push_back(c.name);
    }
    const std::size_t nc = channels.size(), np = pixel_count(w, h);
    std::vector<float> interleaved(np * nc);
    for (std::size_t p = 0; p < np; ++p)
        for (std::size_t c = 0; c < nc; ++c)
            interleaved[p * nc + c] = channels[c].data[p * channels[c].stride + channels[c].offset];
    write_atomically(path, [&](const fs::path& tmp) {
        codec::WriteSpec spec = float_spec(w, h, names);
        add_attributes(spec, attributes);
        write_with_codec(path, tmp, spec, interleaved.data());
    });
}

bool ChannelImage::has(const std::string& name) const {
    return std::find(names.begin(), names.end(), name) != names.end();
}

std::vector<float> ChannelImage::channel(const std::string& name) const {
    auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end()) {
        std::string all;
        for (const auto& n : names) all += (all.empty() ? "" : ", ") + n;
        fail("the image has no channel '{}' (it has {})", name, all);
    }
    const std::size_t c = static_cast<std::size_t>(it - names.begin()), nc = names.size();
    std::vector<float> v(pixel_count(width, height));
    for (std::size_t p = 0; p < v.size(); ++p) v[p] = data[p * nc + c];
    return v;
}

ChannelImage read_image_channels(const fs::path& path) {
    std::error_code ec;
    if (!fs::exists(path, ec)) fail("cannot read image '{}': no such file", path.string());
    std::unique_ptr<codec::Reader> in = open_reader(path, "cannot read image");
    const codec::Header& spec = in->header();
    ChannelImage img;
    img.width = spec.width;
    img.height = spec.height;
    img.names = spec.channel_names;
    img.data.resize(pixel_count(spec.width, spec.height) * spec.channels);
    if (!in->read(spec.channels, codec::Pixel::Float, img.data.data(), 0))
        fail("cannot read image '{}': {}", path.string(), in->error());
    return img;
}

Image read_image(const fs::path& path) {
    std::error_code ec;
    if (!fs::exists(path, ec)) fail("cannot read image '{}': no such file", path.string());
    if (fs::is_directory(path, ec)) fail("cannot read image '{}': it is a folder", path.string());
    std::unique_ptr<codec::Reader> in = open_reader(path, "cannot read image");
    const codec::Header spec = in->header();
    int channels = spec.channels;
    if (channels < 1 || spec.width <= 0 || spec.height <= 0)
        fail("cannot read image '{}': it holds no pixels", path.string());
    bool srgb = ascii_lower(spec.colorspace) == "srgb";
    // 8-bit sRGB files are read as codes and decoded in double through a table, so each code
    // maps to exactly srgb_decode(code / 255); everything else is read as float.
    bool codes = srgb && spec.storage == codec::Storage::UInt8;
    std::size_t n = pixel_count(spec.width, spec.height) * channels;
    std::vector<float> data(n);
    std::vector<std::uint8_t> code_data(codes ? n : 0);
    bool ok = codes ? in->read(channels, codec::Pixel::UInt8, code_data.data(), 0)
                    : in->read(channels, codec::Pixel::Float, data.data(), 0);
    if (!ok) fail("cannot read image '{}': {}", path.string(), in->error());
    in.reset();
    if (codes) {
        float table[256];
        for (int c = 0; c < 256; ++c) table[c] = static_cast<float>(srgb_decode(c / 255.0));
        for (std::size_t i = 0; i < n; ++i) data[i] = table[code_data[i]];
    } else if (srgb) {
        for (float& v : data) v = static_cast<float>(srgb_decode(v));
    }

    // First three channels; one or two channels (grey, grey + alpha) give grey RGB.
    Image image(spec.width, spec.height);
    for (std::size_t p = 0; p < pixel_count(spec.width, spec.height); ++p)
        for (int c = 0; c < 3; ++c)
            image.rgb[p * 3 + c] = data[p * channels + (channels >= 3 ? c : 0)];
    return image;
}

ErrorMetrics compare_images(const Image& x, const Image& r, double relmse_eps) {
    if (x.width != r.width || x.height != r.height)
        fail("cannot compare images: sizes differ ({}x{} vs reference {}x{})", x.width, x.height,
             r.width, r.height);
    std::size_t n = pixel_count(x.width, x.height) * 3;
    if (x.rgb.size() != n || r.rgb.size() != n)
        fail("cannot compare images: pixel buffers do not match their {}x{} size", x.width,
             x.height);

    ErrorMetrics m;
    if (n == 0) return m;
    double se = 0.0, rel = 0.0, ae = 0.0;
    std::size_t max_at = 0;
    for (std::size_t i = 0; i < n; ++i) {
        double d = static_cast<double>(x.rgb[i]) - static_cast<double>(r.rgb[i]);
        double rv = r.rgb[i];
        se += d * d;
        rel += d * d / (rv * rv + relmse_eps);
        ae += std::abs(d);
        if (std::abs(d) > m.max_abs) {
            m.max_abs = std::abs(d);
            max_at = i;
        }
    }
    m.rmse = std::sqrt(se / static_cast<double>(n));
    m.relmse = rel / static_cast<double>(n);
    m.mae = ae / static_cast<double>(n);
    std::size_t pixel = max_at / 3;
    m.max_x = static_cast<int>(pixel % static_cast<std::size_t>(x.width));
    m.max_y = static_cast<int>(pixel / static_cast<std::size_t>(x.width));
    return m;
}

Image downsample_box(const Image& image, int factor) {
    if (factor < 1) fail("cannot downsample: factor {} is not positive", factor);
    if (image.width % factor != 0 || image.height % factor != 0)
        fail("cannot downsample a {}x{} image by {}: the factor must divide both sides",
             image.width, image.height, factor);
    Image out(image.width / factor, image.height / factor);
    double inv = 1.0 / (static_cast<double>(factor) * factor);
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x) {
            double sum[3] = {0.0, 0.0, 0.0};
            for (int sy = 0; sy < factor; ++sy)
                for (int sx = 0; sx < factor; ++sx) {
                    const float* p = image.pixel(x * factor + sx, y * factor + sy);
                    for (int c = 0; c < 3; ++c) sum[c] += p[c];
                }
            float* o = out.pixel(x, y);
            for (int c = 0; c < 3; ++c) o[c] = static_cast<float>(sum[c] * inv);
        }
    return out;
}

}  // namespace wp
