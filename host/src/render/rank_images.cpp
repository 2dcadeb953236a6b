#include "render/rank_images.hpp"

#include "multi/rank_bytes.hpp"

#include <cstring>
#include <string>
#include <utility>

namespace clsph::render {
namespace {

void put(std::string& out, const DepthImage& im) {
    multi::put_word(out, im.width);
    multi::put_word(out, im.height);
    multi::put_bytes(out, im.depth);
    multi::put_bytes(out, im.colour);
}
void take(multi::ByteReader& in, DepthImage& im) {
    im.width = static_cast<std::uint32_t>(in.word());
    im.height = static_cast<std::uint32_t>(in.word());
    in.take(im.depth);
    in.take(im.colour);
}

void put(std::string& out, const SplatImage& im) {
    multi::put_word(out, im.width);
    multi::put_word(out, im.height);
    multi::put_bytes(out, im.depth);
    multi::put_bytes(out, im.thickness);
    multi::put_bytes(out, im.field);
    std::uint64_t unit = 0;
    std::memcpy(&unit, &im.unit, 8);
    multi::put_word(out, unit);
}
void take(multi::ByteReader& in, SplatImage& im) {
    im.width = static_cast<std::uint32_t>(in.word());
    im.height = static_cast<std::uint32_t>(in.word());
    in.take(im.depth);
    in.take(im.thickness);
    in.take(im.field);
    const std::uint64_t unit = in.word();
    std::memcpy(&im.unit, &unit, 8);
}

template <class Image>
SlabImages<Image> gather(Ranks& ranks, const SlabImages<Image>& mine) {
    std::string bytes;
    for (const auto& [slab, im] : mine) {
        multi::put_word(bytes, slab);
        put(bytes, im);
    }
    SlabImages<Image> all;
    for (const auto& part : ranks.gather_text_to(std::move(bytes), 0))
        for (multi::ByteReader in(part, "images"); !in.done();) {
            const auto slab = static_cast<std::size_t>(in.word());
            Image im;
            take(in, im);
            all.emplace_back(slab, std::move(im));
        }
    return all;
}

}  // namespace

SlabImages<DepthImage> gather_to_rank0(Ranks& ranks, const SlabImages<DepthImage>& mine) { return gather(ranks, mine); }
SlabImages<SplatImage> gather_to_rank0(Ranks& ranks, const SlabImages<SplatImage>& mine) { return gather(ranks, mine); }

}  // namespace clsph::render
