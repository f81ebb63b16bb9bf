// oiio_codec.cpp — image/codec.h's codec on OpenImageIO: built as the module
// libwavepath_oiio.so (loaded by the wavepath binary on first use) and linked directly into
// wavepath_image_tests and the fuzzers. No exception leaves these functions: OIIO's errors,
// and any exception its calls throw, come back as messages.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <exception>
#include <memory>
#include <string>

#include "image/codec.h"

namespace {

using namespace wp::codec;

// OIIO's messages end in a newline; an empty one says nothing.
std::string trimmed(std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
    return s.empty() ? std::string("OpenImageIO gave no reason") : s;
}

OIIO::TypeDesc type_of(Pixel p) {
    switch (p) {
        case Pixel::UInt8: return OIIO::TypeDesc::UINT8;
        case Pixel::UInt16: return OIIO::TypeDesc::UINT16;
        case Pixel::Float: break;
    }
    return OIIO::TypeDesc::FLOAT;
}

Storage storage_of(OIIO::TypeDesc t) {
    switch (t.basetype) {
        case OIIO::TypeDesc::UINT8: return Storage::UInt8;
        case OIIO::TypeDesc::INT8: return Storage::Int8;
        case OIIO::TypeDesc::UINT16: return Storage::UInt16;
        case OIIO::TypeDesc::INT16: return Storage::Int16;
        case OIIO::TypeDesc::HALF: return Storage::Half;
        case OIIO::TypeDesc::FLOAT: return Storage::Float;
        case OIIO::TypeDesc::DOUBLE: return Storage::Double;
        default: return Storage::Other;
    }
}

OIIO::ImageSpec reader_config(bool straight_alpha) {
    OIIO::ImageSpec config;
    if (straight_alpha) config.attribute("oiio:UnassociatedAlpha", 1);
    return config;
}

class OiioReader final : public Reader {
public:
    // The proxy (images in memory) outlives the reader: members are destroyed in reverse.
    std::unique_ptr<OIIO::Filesystem::IOMemReader> proxy;
    std::unique_ptr<OIIO::ImageInput> in;
    OIIO::ImageSpec spec;
    Header head;

    void set_spec(const OIIO::ImageSpec& s) {
        spec = s;  // a copy: reading may change the reader's
        head.width = s.width;
        head.height = s.height;
        head.depth = s.depth;
        head.channels = s.nchannels;
        head.deep = s.deep;
        head.storage = storage_of(s.format);
        head.channel_names.clear();
        for (int c = 0; c < s.nchannels; ++c) head.channel_names.push_back(s.channel_name(c));
        head.colorspace = s.get_string_attribute("oiio:ColorSpace");
        head.gamma = s.get_float_attribute("oiio:Gamma", 0.0f);
    }
    ~OiioReader() override {
        if (in) in->close();
    }
    const Header& header() const override { return head; }
    bool read(int channels, Pixel type, void* data, std::ptrdiff_t pixel_stride) override {
        try {
            return in->read_image(0, 0, 0, channels, type_of(type), data,
                                  pixel_stride > 0 ? OIIO::stride_t(pixel_stride) : OIIO::AutoStride);
        } catch (const std::exception& e) {
            message = e.what();
            return false;
        }
    }
    std::optional<std::string> attribute(const std::string& name) const override {
        const OIIO::ParamValue* p = spec.find_attribute(name);
        if (!p) return std::nullopt;
        return p->get_string();
    }
    std::string error() override {
        if (!message.empty()) return message;
        return trimmed(in->geterror());
    }

private:
    std::string message;
};

std::unique_ptr<Reader> open_file(const std::string& path, bool straight_alpha, std::string* error) {
    try {
        auto r = std::make_unique<OiioReader>();
        const OIIO::ImageSpec config = reader_config(straight_alpha);
        r->in = OIIO::ImageInput::open(path, &config);
        if (!r->in) {
            *error = trimmed(OIIO::geterror());
            return nullptr;
        }
        r->set_spec(r->in->spec());
        return r;
    } catch (const std::exception& e) {
        *error = e.what();
        return nullptr;
    }
}

std::unique_ptr<Reader> open_memory(const std::string& name, const std::string& bytes, bool straight_alpha,
                                    std::string* error) {
    try {
        auto r = std::make_unique<OiioReader>();
        r->proxy = std::make_unique<OIIO::Filesystem::IOMemReader>(bytes.data(), bytes.size());
        // create() with a proxy picks the reader by the name's extension and, when that
        // reader does not accept the bytes, by trying the others.
        r->in = OIIO::ImageInput::create(name, false, nullptr, r->proxy.get());
        if (!r->in) {
            *error = trimmed(OIIO::geterror());
            return nullptr;
        }
        if (!r->in->supports("ioproxy")) {
            *error = "the " + std::string(r->in->format_name()) + " reader cannot read from memory";
            r->in.reset();
            return nullptr;
        }
        if (!r->in->set_ioproxy(r->proxy.get())) {
            *error = trimmed(r->in->geterror());
            r->in.reset();
            return nullptr;
        }
        OIIO::ImageSpec spec;
        if (!r->in->open(name, spec, reader_config(straight_alpha))) {
            *error = trimmed(r->in->geterror());
            r->in.reset();
            return nullptr;
        }
        r->set_spec(r->in->spec());
        return r;
    } catch (const std::exception& e) {
        *error = e.what();
        return nullptr;
    }
}

bool write(const std::string& path, const std::string& format, const WriteSpec& ws, const void* data,
           std::string* error) {
    try {
        const OIIO::TypeDesc type = type_of(ws.type);
        OIIO::ImageSpec spec(ws.width, ws.height, static_cast<int>(ws.channel_names.size()), type);
        spec.channelnames = ws.channel_names;
        for (const wp::ImageAttribute& a : ws.attributes) {
            if (a.integer)
                spec.attribute(a.name, std::stoi(a.value));
            else
                spec.attribute(a.name, a.value);
        }
        std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(format.empty() ? path : format);
        if (!out) {
            *error = trimmed(OIIO::geterror());
            return false;
        }
        if (!out->open(path, spec)) {
            *error = trimmed(out->geterror());
            return false;
        }
        if (!out->write_image(type, data)) {
            *error = trimmed(out->geterror());
            out->close();
            return false;
        }
        if (!out->close()) {
            *error = trimmed(out->geterror());
            return false;
        }
        return true;
    } catch (const std::exception& e) {
        *error = e.what();
        return false;
    }
}

const Codec kCodec = {open_file, open_memory, write};

}  // namespace

extern "C" __attribute__((visibility("default"))) const wp::codec::Codec* wp_image_codec_v1() { return &kCodec; }
