// codec.h — reading and writing image files, behind one small interface.
//
// The codec is OpenImageIO (src/oiio/oiio_codec.cpp). Debian's libOpenImageIO pulls in
// some 260 shared libraries (OpenCV, FFmpeg, GDAL, GStreamer, …); a program linked with it
// spends 0.15–0.4 s in the dynamic linker before main() on every start, whatever it does
// (docs/performance.md, "Cold start"). So the wavepath binary does not link it: the codec is
// a module, libwavepath_oiio.so, loaded with dlopen(RTLD_LOCAL) the first time a file is
// read or written (image_codec() below). A render reaches its first frame without it and
// loads it to write its image; `--help`, `bench`, `info` and the rest never load it.
// Programs that link the codec's object code directly (wavepath_image_tests,
// wavepath_parser_tests, the fuzzers) use it as linked, without the module.
//
// Every function of the interface reports failure through its return value and a message,
// never by exception, so nothing unwinds across the module boundary; image.cpp and
// texture.cpp turn the messages into wp::Error with their own wording.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "image/image.h"  // ImageAttribute

namespace wp::codec {

// A file's storage type (of its first channel); Other: anything else (e.g. 32-bit ints).
enum class Storage { UInt8, Int8, UInt16, Int16, Half, Float, Double, Other };

// The pixel types wavepath reads into and writes from memory.
enum class Pixel { UInt8, UInt16, Float };

// The first subimage's header.
struct Header {
    int width = 0, height = 0, depth = 1, channels = 0;
    bool deep = false;
    Storage storage = Storage::Other;
    std::vector<std::string> channel_names;
    std::string colorspace;  // the "oiio:ColorSpace" attribute ("" when absent)
    float gamma = 0.0f;      // "oiio:Gamma" (0 when absent; a PNG gAMA of 1.0 gives 1)
};

class Reader {
public:
    virtual ~Reader() = default;
    virtual const Header& header() const = 0;
    // The first `channels` channels of every pixel, converted to `type`, pixel p at
    // data + p * pixel_stride bytes (0: contiguous). False on failure (error() says why).
    virtual bool read(int channels, Pixel type, void* data, std::ptrdiff_t pixel_stride) = 0;
    // Header attribute `name` as text; nothing when the file has none.
    virtual std::optional<std::string> attribute(const std::string& name) const = 0;
    virtual std::string error() = 0;
};

struct WriteSpec {
    int width = 0, height = 0;
    std::vector<std::string> channel_names;  // their count is the channel count
    Pixel type = Pixel::Float;               // of the data in memory and in the file
    std::vector<ImageAttribute> attributes;  // e.g. oiio:ColorSpace, compression
};

struct Codec {
    // Opens a file (header read, no pixels). straight_alpha: colour and alpha as stored
    // (readers otherwise premultiply straight alpha). Null with *error set on failure.
    std::unique_ptr<Reader> (*open_file)(const std::string& path, bool straight_alpha, std::string* error);
    // Opens an image held in memory (`bytes` must outlive the reader); `name` picks the
    // reader by its extension, else each reader is tried.
    std::unique_ptr<Reader> (*open_memory)(const std::string& name, const std::string& bytes,
                                           bool straight_alpha, std::string* error);
    // Writes `data` (spec.type, interleaved channels) to `path`, the format chosen by its
    // extension, or by `format` ("png", ...) when not empty. False with *error on failure.
    bool (*write)(const std::string& path, const std::string& format, const WriteSpec& spec, const void* data,
                  std::string* error);
};

// The codec: the one linked into this program, else the module, loaded on first use from
// $WP_IMAGE_MODULE alone when that is set, else from next to the executable, then from the
// build tree it was built in. Throws wp::Error naming the paths tried and dlopen's reason
// when none loads.
const Codec& image_codec();

// Throws image_codec()'s error when no candidate file of the module exists (without loading
// it): commands that will write an image call it before their work, so that a missing module
// is not found only after a render.
void check_available();

}  // namespace wp::codec

// The module's one entry point (C linkage, so dlsym finds it by this name).
extern "C" const wp::codec::Codec* wp_image_codec_v1();
