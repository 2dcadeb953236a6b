// PNG through stb_image_write / stb_image (Debian libstb-dev), compiled into the library here so a
// host program needs no image library of its own.
#include "clsph/error.hpp"
#include "clsph/render.hpp"

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#define STBI_ONLY_PNG
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wdouble-promotion"
#endif
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#include <cstdio>

namespace clsph {

void write_png(const std::string& path, const Image& image) {
    if (image.width == 0 || image.height == 0 || image.rgb.size() != std::size_t{3} * image.width * image.height)
        throw Error(path + ": the image is empty or its pixels do not match its size");
    const std::string tmp = path + ".tmp";
    if (!stbi_write_png(tmp.c_str(), static_cast<int>(image.width), static_cast<int>(image.height), 3, image.rgb.data(),
                        static_cast<int>(3 * image.width)))
        throw Error("cannot write " + path);
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        std::remove(tmp.c_str());
        throw Error("cannot rename " + tmp + " to " + path);
    }
}

Image read_png(const std::string& path) {
    int w = 0, h = 0, n = 0;
    unsigned char* data = stbi_load(path.c_str(), &w, &h, &n, 3);
    if (!data) throw Error("cannot read " + path + " as PNG: " + (stbi_failure_reason() ? stbi_failure_reason() : "unknown"));
    Image im;
    im.width = static_cast<std::uint32_t>(w);
    im.height = static_cast<std::uint32_t>(h);
    im.rgb.assign(data, data + std::size_t{3} * im.width * im.height);
    stbi_image_free(data);
    return im;
}

}  // namespace clsph
