// exr_cxx_shim.cpp: OpenEXR C++ decoding (Imf::InputFile over an in-memory stream) behind the C
// interface of exr_cxx_shim.h, for compressions OpenEXRCore 3.1 cannot decode (DWAA/DWAB).
// No exception crosses the C boundary.
#include "io/envmap/exr_cxx_shim.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <Iex.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>

namespace {

// Read-only stream over caller-owned bytes. Reading past the end throws (the library turns
// that into an exception the caller sees as "truncated").
class MemIStream : public Imf::IStream {
  public:
    MemIStream(const unsigned char *d, size_t n) : Imf::IStream("memory"), d_(d), n_(n), p_(0) {}
    bool read(char c[], int n) override {
        if (n < 0 || p_ > n_ || static_cast<uint64_t>(n) > n_ - p_)
            throw Iex::InputExc("unexpected end of file");
        std::memcpy(c, d_ + p_, static_cast<size_t>(n));
        p_ += static_cast<uint64_t>(n);
        return p_ < n_;
    }
    uint64_t tellg() override { return p_; }
    void seekg(uint64_t pos) override { p_ = pos; }
    void clear() override {}

  private:
    const unsigned char *d_;
    uint64_t n_, p_;
};

void set_err(char *err, size_t size, const char *msg) {
    if (!err || !size) return;
    std::snprintf(err, size, "%s", msg);
    for (char *c = err; *c; c++)
        if (*c == '\n' || *c == '\r') *c = ' ';
}

} // namespace

extern "C" int sl_exrcxx_read_planes(const unsigned char *data, size_t n, int w, int h, int nplanes,
                                     const char *const *names, float *const *planes, char *err,
                                     size_t err_size) {
    try {
        MemIStream stream(data, n);
        Imf::InputFile file(stream);
        const Imath::Box2i dw = file.header().dataWindow();
        int64_t fw = int64_t(dw.max.x) - dw.min.x + 1, fh = int64_t(dw.max.y) - dw.min.y + 1;
        if (fw != w || fh != h) {
            set_err(err, err_size, "C++ reader sees a different data window");
            return -1;
        }
        const Imf::ChannelList &cl = file.header().channels();
        Imf::FrameBuffer fb;
        for (int i = 0; i < nplanes; i++) {
            const Imf::Channel *ch = cl.findChannel(names[i]);
            if (!ch || ch->xSampling != 1 || ch->ySampling != 1) {
                char msg[160];
                std::snprintf(msg, sizeof msg, "channel %.64s missing or subsampled", names[i]);
                set_err(err, err_size, msg);
                return -1;
            }
            fb.insert(names[i], Imf::Slice::Make(Imf::FLOAT, planes[i], dw, sizeof(float),
                                                 sizeof(float) * static_cast<size_t>(w)));
        }
        file.setFrameBuffer(fb);
        file.readPixels(dw.min.y, dw.max.y);
        return 0;
    } catch (const std::exception &ex) {
        set_err(err, err_size, ex.what());
    } catch (...) {
        set_err(err, err_size, "unknown C++ exception");
    }
    return -1;
}
