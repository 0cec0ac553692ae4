// Uncompressed scanline OpenEXR, written and read without OpenImageIO (see image_codec.hpp).
//
// File layout (OpenEXR 2 "Technical Introduction", single-part scanline): the magic number
// 76 2f 31 01, a version word (2), the header as attributes `name\0 type\0 int32 size value`
// ended by an empty name, an offset table with one uint64 file offset per scanline block, and the
// blocks. With compression NONE a block is one scanline: int32 y, int32 byte count, then each
// channel's row in the header's channel order (channels are listed sorted by name, so RGBA is
// stored A, B, G, R). Everything is little-endian.
#include "../image_codec.hpp"

#include <welkin/error.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>

namespace welkin::detail {

namespace {

void putBytes(std::string& s, const void* p, size_t n) { s.append(static_cast<const char*>(p), n); }
void putI32(std::string& s, int32_t v) {
    for (int i = 0; i < 4; ++i) s.push_back(char((uint32_t(v) >> (8 * i)) & 0xff));
}
void putU64(std::string& s, uint64_t v) {
    for (int i = 0; i < 8; ++i) s.push_back(char((v >> (8 * i)) & 0xff));
}
void putF32(std::string& s, float f) {
    uint32_t u;
    std::memcpy(&u, &f, 4);
    putI32(s, int32_t(u));
}
void putAttr(std::string& s, const char* name, const char* type, const std::string& value) {
    s += name;
    s.push_back('\0');
    s += type;
    s.push_back('\0');
    putI32(s, int32_t(value.size()));
    s += value;
}

// The channel names (sorted, as EXR stores them) and, for each, the source channel in `Image`.
bool channelLayout(int channels, std::vector<std::pair<std::string, int>>& out) {
    switch (channels) {
        case 1: out = {{"Y", 0}}; return true;
        case 2: out = {{"A", 1}, {"Y", 0}}; return true;
        case 3: out = {{"B", 2}, {"G", 1}, {"R", 0}}; return true;
        case 4: out = {{"A", 3}, {"B", 2}, {"G", 1}, {"R", 0}}; return true;
        default: return false;
    }
}

float halfToFloat(uint16_t h) {
    const uint32_t sign = uint32_t(h >> 15) << 31;
    uint32_t exp = (h >> 10) & 0x1f, man = h & 0x3ff, bits;
    if (exp == 0) {
        if (man == 0) {
            bits = sign;
        } else {  // subnormal: 2^-24 * man
            float f = std::ldexp(float(man), -24);
            return (h >> 15) ? -f : f;
        }
    } else if (exp == 31) {
        bits = sign | 0x7f800000u | (man << 13);
    } else {
        bits = sign | ((exp + 112) << 23) | (man << 13);
    }
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
}

struct Reader {
    const std::string& data;
    const std::string& path;
    size_t pos = 0;
    [[noreturn]] void fail(const std::string& why) const { throw Error("readImage('" + path + "'): EXR " + why); }
    void need(size_t n) const {
        if (n > data.size() || pos > data.size() - n) fail("is truncated");
    }
    std::string cstr() {
        size_t end = data.find('\0', pos);
        if (end == std::string::npos || end - pos > 255) fail("header has an unterminated name");
        std::string s = data.substr(pos, end - pos);
        pos = end + 1;
        return s;
    }
    uint32_t u32() {
        need(4);
        uint32_t v = 0;
        for (int i = 0; i < 4; ++i) v |= uint32_t(uint8_t(data[pos + i])) << (8 * i);
        pos += 4;
        return v;
    }
    int32_t i32() { return int32_t(u32()); }
    uint64_t u64() {
        need(8);
        uint64_t v = 0;
        for (int i = 0; i < 8; ++i) v |= uint64_t(uint8_t(data[pos + i])) << (8 * i);
        pos += 8;
        return v;
    }
};

}  // namespace

std::string writeExrUncompressed(const Image& img, const std::string& path) {
    std::vector<std::pair<std::string, int>> chans;
    if (!channelLayout(img.channels, chans)) return std::to_string(img.channels) + " channels (EXR: 1 to 4)";
    std::string s;
    const unsigned char magic[8] = {0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0};
    putBytes(s, magic, 8);
    std::string chlist;
    for (const auto& [name, src] : chans) {
        chlist += name;
        chlist.push_back('\0');
        putI32(chlist, 2);  // FLOAT
        chlist.append(4, '\0');  // pLinear and three reserved bytes
        putI32(chlist, 1);  // x sampling
        putI32(chlist, 1);  // y sampling
    }
    chlist.push_back('\0');
    putAttr(s, "channels", "chlist", chlist);
    putAttr(s, "compression", "compression", std::string(1, '\0'));  // NO_COMPRESSION
    std::string box;
    putI32(box, 0);
    putI32(box, 0);
    putI32(box, img.width - 1);
    putI32(box, img.height - 1);
    putAttr(s, "dataWindow", "box2i", box);
    putAttr(s, "displayWindow", "box2i", box);
    putAttr(s, "lineOrder", "lineOrder", std::string(1, '\0'));  // INCREASING_Y
    std::string f;
    putF32(f, 1.0f);
    putAttr(s, "pixelAspectRatio", "float", f);
    std::string v2;
    putF32(v2, 0.0f);
    putF32(v2, 0.0f);
    putAttr(s, "screenWindowCenter", "v2f", v2);
    putAttr(s, "screenWindowWidth", "float", f);
    s.push_back('\0');
    const size_t rowBytes = size_t(img.width) * chans.size() * 4;
    const size_t tableAt = s.size();
    const size_t firstBlock = tableAt + 8 * size_t(img.height);
    for (int y = 0; y < img.height; ++y) putU64(s, firstBlock + size_t(y) * (8 + rowBytes));
    for (int y = 0; y < img.height; ++y) {
        putI32(s, y);
        putI32(s, int32_t(rowBytes));
        for (const auto& [name, src] : chans)
            for (int x = 0; x < img.width; ++x) putF32(s, img.at(x, y, src));
    }
    std::ofstream out(path, std::ios::binary);
    if (!out) return "cannot create the file";
    out.write(s.data(), std::streamsize(s.size()));
    out.close();
    return out ? std::string() : std::string("write failed");
}

Image readExrUncompressed(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error("readImage('" + path + "'): cannot open the file");
    const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    Reader r{data, path};
    if (r.u32() != 0x01312f76u) r.fail("magic number missing");
    const uint32_t version = r.u32();
    if ((version & 0xff) != 2) r.fail("version " + std::to_string(version & 0xff) + " (accepted: 2)");
    if (version & 0x1e00) r.fail("is tiled, deep or multi-part (accepted: single-part scanline)");
    struct Channel {
        std::string name;
        int type;
    };
    std::vector<Channel> chans;
    int compression = -1, x0 = 0, y0 = 0, x1 = -1, y1 = -1;
    for (;;) {
        std::string name = r.cstr();
        if (name.empty()) break;
        std::string type = r.cstr();
        const int32_t size = r.i32();
        if (size < 0) r.fail("attribute '" + name + "' has a negative size");
        r.need(size_t(size));
        const size_t end = r.pos + size_t(size);
        if (name == "channels") {
            while (r.pos < end && r.data[r.pos] != '\0') {
                std::string cn = r.cstr();
                int t = r.i32();
                r.need(4);
                r.pos += 4;
                int xs = r.i32(), ys = r.i32();
                if (t != 1 && t != 2) r.fail("channel '" + cn + "' type " + std::to_string(t) + " (accepted: half, float)");
                if (xs != 1 || ys != 1) r.fail("channel '" + cn + "' is subsampled");
                chans.push_back({cn, t});
            }
        } else if (name == "compression") {
            if (size != 1) r.fail("compression attribute size");
            compression = uint8_t(r.data[r.pos]);
        } else if (name == "dataWindow") {
            if (size != 16) r.fail("dataWindow attribute size");
            x0 = r.i32(), y0 = r.i32(), x1 = r.i32(), y1 = r.i32();
        }
        r.pos = end;
    }
    if (compression != 0)
        r.fail("compression " + std::to_string(compression) + " (this build reads uncompressed EXR only; others need WELKIN_IMAGE_IO=OpenImageIO)");
    const int64_t w = int64_t(x1) - x0 + 1, h = int64_t(y1) - y0 + 1;
    if (chans.empty() || chans.size() > 4) r.fail("has " + std::to_string(chans.size()) + " channels (accepted: 1 to 4)");
    checkReadSize(path, w, h, (long long)chans.size());
    // Where each EXR channel goes in the image: R, G, B, A (or Y, A) in that order.
    static const std::array<const char*, 4> order4 = {"R", "G", "B", "A"};
    Image img;
    img.width = int(w);
    img.height = int(h);
    img.channels = int(chans.size());
    std::vector<int> dest(chans.size(), -1);
    for (size_t i = 0; i < chans.size(); ++i) {
        const std::string& n = chans[i].name;
        int d = -1;
        if (n == "Y") d = 0;
        for (int k = 0; k < 4; ++k)
            if (n == order4[k]) d = k;
        if (img.channels == 2 && n == "A") d = 1;
        if (d < 0 || d >= img.channels) d = int(i);  // unknown names keep their stored order
        for (size_t j = 0; j < i; ++j)
            if (dest[j] == d) r.fail("channel names clash ('" + n + "')");
        dest[i] = d;
    }
    img.pixels.assign(size_t(w) * h * img.channels, 0.0f);
    size_t rowBytes = 0;
    for (const auto& c : chans) rowBytes += size_t(w) * (c.type == 2 ? 4 : 2);
    const size_t table = r.pos;
    for (int64_t line = 0; line < h; ++line) {
        r.pos = table + size_t(line) * 8;
        const uint64_t at = r.u64();
        if (at > data.size()) r.fail("offset table points outside the file");
        r.pos = size_t(at);
        const int64_t y = int64_t(r.i32()) - y0;
        const int32_t bytes = r.i32();
        if (y < 0 || y >= h) r.fail("scanline " + std::to_string(y) + " outside the data window");
        if (bytes < 0 || size_t(bytes) != rowBytes) r.fail("scanline has " + std::to_string(bytes) + " bytes, expected " + std::to_string(rowBytes));
        r.need(rowBytes);
        for (size_t c = 0; c < chans.size(); ++c) {
            for (int64_t x = 0; x < w; ++x) {
                float v;
                if (chans[c].type == 2) {
                    uint32_t u = r.u32();
                    std::memcpy(&v, &u, 4);
                } else {
                    r.need(2);
                    uint16_t u = uint16_t(uint8_t(data[r.pos]) | (uint8_t(data[r.pos + 1]) << 8));
                    r.pos += 2;
                    v = halfToFloat(u);
                }
                img.at(int(x), int(y), dest[c]) = v;
            }
        }
    }
    return img;
}

}  // namespace welkin::detail
