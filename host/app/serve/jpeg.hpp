// JPEG frames of the live view (libjpeg-turbo), encoded on a server thread, never the run's.
#pragma once
#include <clsph/render.hpp>

#include <string>

namespace clsph::app::serve {

// The image as a baseline JPEG (4:2:0, `quality` 1..100). Throws clsph::Error with turbojpeg's
// message when encoding fails.
std::string encode_jpeg(const Image& image, int quality = 80);

}  // namespace clsph::app::serve
