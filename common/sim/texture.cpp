#include "sim/texture.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "sim/rng.hpp"

namespace df::sim {
namespace {

uint64_t lattice(double v) { return static_cast<uint64_t>(static_cast<int64_t>(std::floor(v))); }

/// Lattice values of the value noise: a constant 256 x 256 table of hashed values (built once,
/// thread-safe, read-only); a seed picks a shifted window of it, so lookups cost one read instead
/// of a hash. The noise repeats every 256 lattice cells (7.7 m at the finest grain used).
constexpr int kLattice = 256;

const std::vector<float>& lattice_table() {
    static const std::vector<float> table = [] {
        std::vector<float> t(kLattice * kLattice);
        for (int i = 0; i < kLattice * kLattice; ++i)
            t[i] = static_cast<float>(unit_from_bits(mix64(0x1A77ull * 1000003ull + i)));
        return t;
    }();
    return table;
}

double lattice_value(const float* table, uint64_t seed, uint64_t ix, uint64_t iy) {
    const uint64_t sx = (ix + (seed & 0xFF)) & (kLattice - 1);
    const uint64_t sy = (iy + ((seed >> 8) & 0xFF) + ((seed >> 16) & 0xFF) * 7) & (kLattice - 1);
    return table[sy * kLattice + sx];
}

double value_noise(uint64_t seed, double x, double y) {
    const double fx = std::floor(x), fy = std::floor(y);
    const double tx = x - fx, ty = y - fy;
    const double sx = tx * tx * (3 - 2 * tx), sy = ty * ty * (3 - 2 * ty);
    const uint64_t ix = lattice(fx), iy = lattice(fy);
    const float* table = lattice_table().data();
    const double v00 = lattice_value(table, seed, ix, iy),
                 v10 = lattice_value(table, seed, ix + 1, iy);
    const double v01 = lattice_value(table, seed, ix, iy + 1);
    const double v11 = lattice_value(table, seed, ix + 1, iy + 1);
    return (v00 * (1 - sx) + v10 * sx) * (1 - sy) + (v01 * (1 - sx) + v11 * sx) * sy;
}

Rgb sample_photo(const cv::Mat& image, double s, double t) {
    // s, t in [0, 1]: left-to-right, top-to-bottom; bilinear between pixel centres.
    const double x = std::clamp(s * image.cols - 0.5, 0.0, image.cols - 1.0);
    const double y = std::clamp(t * image.rows - 0.5, 0.0, image.rows - 1.0);
    const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
    const int x1 = std::min(x0 + 1, image.cols - 1), y1 = std::min(y0 + 1, image.rows - 1);
    const double ax = x - x0, ay = y - y0;
    const auto* r0 = image.ptr<cv::Vec3b>(y0);
    const auto* r1 = image.ptr<cv::Vec3b>(y1);
    Rgb c;
    for (int k = 0; k < 3; ++k) {
        c[k] = ((r0[x0][k] * (1 - ax) + r0[x1][k] * ax) * (1 - ay) +
                (r1[x0][k] * (1 - ax) + r1[x1][k] * ax) * ay) /
               255.0;
    }
    return c;
}

bool decal_colour(const Decal& decal, const Vec3& p, const SurfacePoint& s, Rgb* colour) {
    const Vec3 normal = decal.right.cross(decal.up);
    if (s.normal.dot(normal) < 0.3) return false;
    const Vec3 rel = p - decal.centre;
    if (std::abs(rel.dot(normal)) > decal.depth) return false;
    const double x = rel.dot(decal.right), y = rel.dot(decal.up);
    const double w = decal.half_width, h = decal.half_height;
    if (std::abs(x) > w + decal.border || std::abs(y) > h + decal.border) return false;
    if (std::abs(x) > w || std::abs(y) > h) {
        *colour = decal.border_colour;
        return true;
    }
    if (!decal.image) {
        *colour = Rgb(0.5, 0.5, 0.5);
        return true;
    }
    *colour = sample_photo(*decal.image, 0.5 * (x / w + 1), 0.5 * (1 - y / h));
    return true;
}

Rgb pattern_colour(const Texture& tx, const SurfacePoint& s, uint64_t seed) {
    const double u = s.u, v = s.v, sc = tx.scale;
    switch (tx.pattern) {
        case Pattern::kSolid:
            return tx.a;
        case Pattern::kChecker: {
            const int64_t parity =
                static_cast<int64_t>(std::floor(u / sc)) + static_cast<int64_t>(std::floor(v / sc));
            return (parity & 1) ? tx.b : tx.a;
        }
        case Pattern::kNoise: {
            const double n = fbm(seed ^ 0x51, u / sc, v / sc);
            return tx.a + (tx.b - tx.a) * std::clamp((n - 0.2) / 0.6, 0.0, 1.0);
        }
        case Pattern::kPlanks: {
            const double length = 6 * sc;
            const double row = std::floor(v / sc);
            const uint64_t irow = lattice(row);
            const double shifted = u + length * hash01(seed, irow, 7);
            const double col = std::floor(shifted / length);
            const double tone = hash01(seed, irow, lattice(col), 11);
            const double streak = value_noise(seed ^ 0x77, shifted / 0.25, v / 0.012);
            Rgb c = tx.a + (tx.b - tx.a) * (0.15 + 0.6 * tone + 0.25 * streak);
            const double du = std::min(shifted - col * length, (col + 1) * length - shifted);
            const double dv = std::min(v - row * sc, (row + 1) * sc - v);
            if (du < 0.003 || dv < 0.002) c *= 0.55;
            return c;
        }
        case Pattern::kTiles: {
            const double fu = u / sc - std::floor(u / sc), fv = v / sc - std::floor(v / sc);
            const double grout = 0.006 / sc;
            if (fu < grout || fv < grout) return tx.b;
            return tx.a * (0.93 + 0.14 * hash01(seed, lattice(u / sc), lattice(v / sc), 3));
        }
        case Pattern::kStripes: {
            const double w = tx.along_v ? v : u;
            return std::fmod(std::abs(w), sc) < 0.5 * sc ? tx.a : tx.b;
        }
        case Pattern::kPanel: {
            const bool inside = u > sc && v > sc && u < s.u_extent - sc && v < s.v_extent - sc;
            return inside ? tx.a : tx.b;
        }
        case Pattern::kRings: {
            const double r = std::hypot(u - 0.5 * s.u_extent, v - 0.5 * s.v_extent);
            return (static_cast<int64_t>(r / sc) & 1) ? tx.b : tx.a;
        }
    }
    return tx.a;
}

}  // namespace

double fbm(uint64_t seed, double x, double y) {
    const uint64_t s1 = mix64(seed + 1), s2 = mix64(seed + 2);
    return (4 * value_noise(seed, x, y) + 2 * value_noise(s1, 2.03 * x, 2.03 * y) +
            value_noise(s2, 4.1 * x, 4.1 * y)) /
           7.0;
}

Rgb albedo(const Material& material, const Vec3& p, const SurfacePoint& s, uint64_t seed) {
    Rgb c;
    bool on_decal = false;
    for (const Decal& decal : material.decals) {
        if (decal_colour(decal, p, s, &c)) {
            on_decal = true;
            break;
        }
    }
    if (on_decal) return c;
    c = pattern_colour(material.texture, s, seed);
    const Texture& tx = material.texture;
    if (tx.grain > 0) {
        // Two octaves are enough for a mottling this fine (and it runs for every pixel).
        const double gu = s.u / tx.grain_scale, gv = s.v / tx.grain_scale + 17.0 * s.face;
        const double g = (2 * value_noise(seed ^ 0x9A, gu, gv) +
                          value_noise(mix64(seed + 0x9B), 2.03 * gu, 2.03 * gv)) /
                         3.0;
        c *= 1.0 + tx.grain * (2.0 * g - 1.0) * 1.6;
    }
    return c.cwiseMax(0.0).cwiseMin(1.0);
}

Material make_material(const std::string& name, Pattern pattern, const Rgb& a, const Rgb& b,
                       double scale, double grain) {
    Material m;
    m.name = name;
    m.texture.pattern = pattern;
    m.texture.a = a;
    m.texture.b = b;
    m.texture.scale = scale;
    m.texture.grain = grain;
    return m;
}

PhotoLibrary::PhotoLibrary(const std::string& folder) : folder_(folder) {
    for (const char* name : {"dog", "horses", "person", "kite", "giraffe", "eagle", "scream"}) {
        cv::Mat bgr;
        try {
            bgr = cv::imread(folder + "/" + name + ".jpg", cv::IMREAD_COLOR);
        } catch (const cv::Exception&) {
            bgr.release();
        }
        if (bgr.empty()) {
            photos_[name] = nullptr;
            continue;
        }
        auto rgb = std::make_shared<cv::Mat>();
        cv::cvtColor(bgr, *rgb, cv::COLOR_BGR2RGB);
        photos_[name] = std::move(rgb);
    }
}

std::shared_ptr<const cv::Mat> PhotoLibrary::get(const std::string& name) const {
    const auto it = photos_.find(name);
    return it == photos_.end() ? nullptr : it->second;
}

std::vector<std::string> PhotoLibrary::missing() const {
    std::vector<std::string> names;
    for (const auto& [name, image] : photos_)
        if (!image) names.push_back(name);
    return names;
}

}  // namespace df::sim
