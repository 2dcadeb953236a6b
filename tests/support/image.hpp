// What image tests share: the background an image has, read from the image itself (not the
// renderer's colour copied into the tests, so they keep checking when the background changes).
#pragma once
#include <clsph/render.hpp>

#include <array>
#include <cstddef>
#include <cstdint>

#include <doctest/doctest.h>

namespace test_image {

// The image's background as the image itself has it: the colour of its corners, where the camera,
// framing the domain with a margin, draws nothing (all four agree, else there is no background to
// tell the drawing from).
inline std::array<std::uint8_t, 3> background_of(const clsph::Image& im) {
    REQUIRE(im.width > 0);
    REQUIRE(im.height > 0);
    const auto pixel = [&](std::size_t x, std::size_t y) {
        const std::size_t at = 3 * (y * im.width + x);
        return std::array<std::uint8_t, 3>{im.rgb[at], im.rgb[at + 1], im.rgb[at + 2]};
    };
    const auto corner = pixel(0, 0);
    CHECK(pixel(im.width - 1, 0) == corner);
    CHECK(pixel(0, im.height - 1) == corner);
    CHECK(pixel(im.width - 1, im.height - 1) == corner);
    return corner;
}

// Pixels of another colour than the background.
inline std::size_t drawn_pixels(const clsph::Image& im) {
    const auto bg = background_of(im);
    std::size_t drawn = 0;
    for (std::size_t p = 0; p < im.rgb.size() / 3; ++p)
        drawn += im.rgb[3 * p] != bg[0] || im.rgb[3 * p + 1] != bg[1] || im.rgb[3 * p + 2] != bg[2];
    return drawn;
}

}  // namespace test_image
