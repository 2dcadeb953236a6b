#include "jpeg.hpp"

#include <clsph/error.hpp>

#include <turbojpeg.h>

#include <memory>

namespace clsph::app::serve {

std::string encode_jpeg(const Image& image, int quality) {
    if (image.width == 0 || image.height == 0 || image.rgb.size() != std::size_t{3} * image.width * image.height)
        throw Error("live view: an empty or malformed image cannot be encoded as JPEG");
    // One compressor per call: encoding runs on several server threads at once, and a handle is
    // cheap next to the encoding itself.
    std::unique_ptr<void, int (*)(tjhandle)> handle(tjInitCompress(), tjDestroy);
    if (!handle) throw Error("live view: cannot start the JPEG encoder");
    unsigned char* out = nullptr;
    unsigned long size = 0;
    const int rc = tjCompress2(handle.get(), image.rgb.data(), static_cast<int>(image.width), 0,
                               static_cast<int>(image.height), TJPF_RGB, &out, &size, TJSAMP_420, quality, TJFLAG_FASTDCT);
    std::unique_ptr<unsigned char, void (*)(unsigned char*)> owned(out, tjFree);
    if (rc != 0) throw Error(std::string("live view: JPEG encoding failed: ") + tjGetErrorStr2(handle.get()));
    return std::string(reinterpret_cast<const char*>(out), size);
}

}  // namespace clsph::app::serve
