// SurfelMap::predict: CPU splatting of the active surfels with a z-buffer.
//
// The image is cut into horizontal bands, one per thread. Each band's task reads the whole map
// in index order, draws the surfels whose pixel box meets its rows, then fills its output rows.
// Every pixel therefore sees the same surfels in the same order with the same arithmetic
// whatever the number of bands (ties keep the lower index), so the output does not depend on
// the thread count. Nothing is stored between the passes: the (inverse) depth buffer is the z
// channel of the vertex image, and big per-call scratch would cost more in page faults than it
// saves.
#include <algorithm>
#include <cmath>
#include <limits>

#include "map/parallel.hpp"
#include "map/surfel_map.hpp"

namespace df::map {
namespace {

constexpr int kMaxImageSide = 32767;
constexpr float kMaxSplatRadiusPx = 64.f;
constexpr float kMinDepthM = 1e-3f;  // nearer centres would overflow the projection
constexpr int kMinBandRows = 8;

/// A surfel as it is drawn: camera frame, with its pixel box.
struct Splat {
    float px, py, pz;    ///< centre, camera frame, metres
    float nx, ny, nz;    ///< unit normal, camera frame
    float plane;         ///< n . p, metres (< 0: the centre faces the camera)
    float radius_sq;     ///< disc radius squared, m^2
    int32_t index;       ///< into surfels()
    int u0, u1, v0, v1;  ///< covered pixels, inclusive, inside the image
    int cu, cv;          ///< the centre's pixel (covered whatever the disc test says)
    float uf, vf;        ///< the centre's projection, pixels
    bool second;         ///< also drawn into the second layer (Renderer::Layers)
};

/// Where a band draws: the main images, and optionally a second layer (its own depth buffer and
/// index image) of the surfels with confidence >= second_min_confidence, drawn in the same pass.
struct Layers {
    ModelPrediction* main = nullptr;
    cv::Mat* second_depth = nullptr;  ///< CV_32FC3 scratch (as main's vertex while drawing)
    cv::Mat* second_index = nullptr;  ///< CV_32SC1
    float second_min_confidence = 0.f;
    bool shade = true;  ///< false: main's vertex, normal and colour are left unspecified
};

/// floor and ceil for |x| < 2^31 without a libm call (baseline x86-64 has no rounding
/// instruction), exact.
inline int floor_int(float x) {
    const int i = static_cast<int>(x);
    return i - static_cast<int>(static_cast<float>(i) > x);
}
inline int ceil_int(float x) {
    const int i = static_cast<int>(x);
    return i + static_cast<int>(static_cast<float>(i) < x);
}

/// Rounds half away from zero, as write_ply does (cv::saturate_cast rounds half to even).
inline uint8_t to_byte(float channel) {
    return static_cast<uint8_t>(std::min(255.f, std::max(0.f, channel)) + 0.5f);
}

Status check_prediction_inputs(const io::Intrinsics& k, int width, int height,
                               const PredictionConfig& config) {
    const auto invalid = [](const std::string& what) {
        return error(StatusCode::kInvalidArgument, "SurfelMap::predict: " + what);
    };
    if (width < 1 || height < 1 || width > kMaxImageSide || height > kMaxImageSide) {
        return invalid("image size must be 1.." + std::to_string(kMaxImageSide) +
                       " on each side, got " + std::to_string(width) + "x" +
                       std::to_string(height));
    }
    if (!(k.fx > 0.0) || !(k.fy > 0.0) || !std::isfinite(k.fx) || !std::isfinite(k.fy) ||
        !std::isfinite(k.cx) || !std::isfinite(k.cy)) {
        return invalid("focal lengths must be positive and intrinsics finite, got fx=" +
                       std::to_string(k.fx) + " fy=" + std::to_string(k.fy) +
                       " cx=" + std::to_string(k.cx) + " cy=" + std::to_string(k.cy));
    }
    if (!(config.max_depth_m >= 0.f) || !std::isfinite(config.max_depth_m)) {
        return invalid("config.max_depth_m must be >= 0 (0 = no limit), got " +
                       std::to_string(config.max_depth_m));
    }
    if (!(config.max_splat_radius_px >= 0.f && config.max_splat_radius_px <= kMaxSplatRadiusPx)) {
        return invalid("config.max_splat_radius_px must be in 0..64, got " +
                       std::to_string(config.max_splat_radius_px));
    }
    if (!(config.min_cos_incidence >= 0.f && config.min_cos_incidence <= 1.f)) {
        return invalid("config.min_cos_incidence must be in 0..1, got " +
                       std::to_string(config.min_cos_incidence));
    }
    if (!(config.layer_tolerance_m >= 0.f) || !(config.layer_tolerance_per_m2 >= 0.f)) {
        return invalid("config.layer_tolerance_m and layer_tolerance_per_m2 must be >= 0, got " +
                       std::to_string(config.layer_tolerance_m) + " and " +
                       std::to_string(config.layer_tolerance_per_m2));
    }
    return Status::ok();
}

/// Everything one predict() call needs, and the three steps of a band.
class Renderer {
  public:
    Renderer(const SurfelMap& map, const Eigen::Isometry3f& world_T_camera, const io::Intrinsics& k,
             int width, int height, int frame_index, const PredictionConfig& config)
        : map_(map),
          surfels_(map.surfels()),
          frame_index_(frame_index),
          config_(config),
          width_(width),
          height_(height),
          fx_(static_cast<float>(k.fx)),
          fy_(static_cast<float>(k.fy)),
          cx_(static_cast<float>(k.cx)),
          cy_(static_cast<float>(k.cy)),
          f_max_(std::max(fx_, fy_)),
          max_depth_(config.max_depth_m > 0.f ? config.max_depth_m
                                              : std::numeric_limits<float>::infinity()),
          cos_sq_(config.min_cos_incidence * config.min_cos_incidence),
          ray_x_(static_cast<size_t>(width)),
          ray_y_(static_cast<size_t>(height)) {
        const Eigen::Isometry3f camera_T_world = world_T_camera.inverse();
        rotation_ = camera_T_world.linear();
        translation_ = camera_T_world.translation();
        for (int u = 0; u < width; ++u) ray_x_[u] = (static_cast<float>(u) - cx_) / fx_;
        for (int v = 0; v < height; ++v) ray_y_[v] = (static_cast<float>(v) - cy_) / fy_;
    }

    /// Draws and shades the rows [v_begin, v_end) of the layers' images (allocated, width x
    /// height).
    void render_band(int v_begin, int v_end, const Layers& layers) const {
        ModelPrediction& out = *layers.main;
        const bool two = layers.second_index != nullptr;
        for (int v = v_begin; v < v_end; ++v) {
            auto* vertex_row = out.vertex.ptr<cv::Vec3f>(v);
            std::fill(vertex_row, vertex_row + width_, cv::Vec3f(0.f, 0.f, 0.f));
            int32_t* index_row = out.index.ptr<int32_t>(v);
            std::fill(index_row, index_row + width_, -1);
            if (two) {
                auto* depth_row = layers.second_depth->ptr<cv::Vec3f>(v);
                std::fill(depth_row, depth_row + width_, cv::Vec3f(0.f, 0.f, 0.f));
                int32_t* second_row = layers.second_index->ptr<int32_t>(v);
                std::fill(second_row, second_row + width_, -1);
            }
        }
        Splat s;
        for (size_t i = 0; i < surfels_.size(); ++i) {
            if (!project(i, v_begin, v_end, s)) continue;
            const int begin = std::max(s.v0, v_begin), end = std::min(s.v1 + 1, v_end);
            if (two && surfels_[i].confidence >= layers.second_min_confidence) {
                draw<true>(s, begin, end, out.vertex, out.index, layers.second_depth,
                           layers.second_index);
            } else {
                draw<false>(s, begin, end, out.vertex, out.index, nullptr, nullptr);
            }
        }
        if (layers.shade) {
            for (int v = v_begin; v < v_end; ++v) shade(v, out);
        }
    }

  private:
    /// The splat of surfel i if it is drawn and its pixel box meets the rows [v_begin, v_end).
    bool project(size_t i, int v_begin, int v_end, Splat& s) const {
        const Surfel& surfel = surfels_[i];
        if (!map_.is_active(surfel, frame_index_) ||
            !(surfel.confidence >= config_.min_confidence)) {
            return false;
        }
        const Eigen::Vector3f& q = surfel.position;
        const Eigen::Matrix3f& r = rotation_;
        // Depth and row first: most surfels miss a band, and these decide it.
        s.pz = r(2, 0) * q.x() + r(2, 1) * q.y() + r(2, 2) * q.z() + translation_.z();
        if (!(s.pz > kMinDepthM) || s.pz > max_depth_) return false;
        s.py = r(1, 0) * q.x() + r(1, 1) * q.y() + r(1, 2) * q.z() + translation_.y();
        const float inv_z = 1.f / s.pz;
        const float radius_px =
            config_.splat ? std::min(surfel.radius * f_max_ * inv_z, config_.max_splat_radius_px)
                          : 0.f;
        const float vf = fy_ * s.py * inv_z + cy_;
        // Also rejects NaN, and keeps the integer conversions below in range.
        if (!(vf > -radius_px - 1.f && vf < static_cast<float>(height_) + radius_px + 1.f)) {
            return false;
        }
        s.cv = floor_int(vf + 0.5f);
        s.vf = vf;
        s.v0 = std::max(0, std::min(s.cv, ceil_int(vf - radius_px)));
        s.v1 = std::min(height_ - 1, std::max(s.cv, floor_int(vf + radius_px)));
        if (s.v0 > s.v1 || s.v1 < v_begin || s.v0 >= v_end) return false;

        s.px = r(0, 0) * q.x() + r(0, 1) * q.y() + r(0, 2) * q.z() + translation_.x();
        const Eigen::Vector3f n = r * surfel.normal;
        s.nx = n.x();
        s.ny = n.y();
        s.nz = n.z();
        s.plane = s.nx * s.px + s.ny * s.py + s.nz * s.pz;
        if (!(s.plane < 0.f)) return false;  // seen from behind
        const float uf = fx_ * s.px * inv_z + cx_;
        if (!(uf > -radius_px - 1.f && uf < static_cast<float>(width_) + radius_px + 1.f)) {
            return false;
        }
        s.cu = floor_int(uf + 0.5f);
        s.uf = uf;
        s.u0 = std::max(0, std::min(s.cu, ceil_int(uf - radius_px)));
        s.u1 = std::min(width_ - 1, std::max(s.cu, floor_int(uf + radius_px)));
        if (s.u0 > s.u1) return false;
        s.radius_sq = surfel.radius * surfel.radius;
        s.index = static_cast<int32_t>(i);
        return true;
    }

    /// z-buffers the splat into the rows [v_begin, v_end). The buffer, in the vertex's z, holds
    /// inverse depth (0 = empty): it is affine in the pixel ray, so no division per pixel.
    /// Splat mode also keeps, in the vertex's x, the squared pixel distance from the winner's
    /// projected centre. A splat wins a pixel when it is in front of the winner by more than the
    /// layer tolerance, or within that tolerance and its centre is nearer the pixel: of the
    /// overlapping discs of one surface the pixel gets the surfel it belongs to, not the one whose
    /// noise put it nearest the camera (a plain z-test biases unaveraged surfaces towards the
    /// camera by about a noise sigma). Points mode z-tests the centres.
    /// kSecond: the splat is also z-buffered into the second layer (second_depth, second_index),
    /// with the same per-pixel tests computed once.
    template <bool kSecond>
    void draw(const Splat& s, int v_begin, int v_end, cv::Mat& depth, cv::Mat& index_image,
              cv::Mat* second_depth, cv::Mat* second_index) const {
        // Locals, not members: the stores below are floats and could alias any float member,
        // which would reload every one of them per pixel.
        const float inv_plane = 1.f / s.plane;
        const float nx = s.nx * inv_plane, ny = s.ny * inv_plane, nz = s.nz * inv_plane;
        const float px = s.px, py = s.py, pz = s.pz, radius_sq = s.radius_sq;
        const float cos_sq_plane = cos_sq_ * inv_plane * inv_plane;
        const float inv_pz = 1.f / pz;
        // Tolerance a + b z^2 in depth is, in inverse depth w = 1/z, about a w^2 + b.
        const float tol_a = config_.layer_tolerance_m, tol_b = config_.layer_tolerance_per_m2;
        const float uf = s.uf, vf = s.vf;
        const int32_t index = s.index;
        const int u0 = s.u0, u1 = s.u1, cu = s.cu, cv = s.cv;
        const float* ray_x = ray_x_.data();
        const bool splat = config_.splat;
        for (int v = v_begin; v < v_end; ++v) {
            const float y = ray_y_[v];
            const float row_inv = ny * y + nz;
            const float y_sq_1 = y * y + 1.f;
            const float dv = static_cast<float>(v) - vf;
            float* vertex_row = depth.ptr<float>(v);
            int32_t* index_row = index_image.ptr<int32_t>(v);
            float* second_row = kSecond ? second_depth->ptr<float>(v) : nullptr;
            int32_t* second_index_row = kSecond ? second_index->ptr<int32_t>(v) : nullptr;
            for (int u = u0; u <= u1; ++u) {
                const float x = ray_x[u];
                // The pixel's ray d = (x, y, 1) meets the plane n.X = n.p at depth t with
                // 1/t = n.d / n.p. It faces the surfel (not behind, not grazing) when n.d < 0
                // and (n.d)^2 >= cos^2 |d|^2, i.e. 1/t > 0 and (1/t)^2 >= cos^2 |d|^2 / (n.p)^2.
                const float inv_t = nx * x + row_inv;
                const bool facing =
                    (inv_t > 0.f) & (inv_t * inv_t >= cos_sq_plane * (x * x + y_sq_1));
                float& inv_depth = vertex_row[3 * u + 2];
                // Branch-free below: on a surface the winner among overlapping splats is a coin
                // toss, which a branch predictor loses half the time.
                bool wins;
                if (splat) {
                    // |t d - p|^2 <= r^2  <=>  |d - p / t|^2 <= r^2 / t^2.
                    const float dx = x - px * inv_t;
                    const float dy = y - py * inv_t;
                    const float dz = 1.f - pz * inv_t;
                    const bool on_disc =
                        (dx * dx + dy * dy + dz * dz <= radius_sq * inv_t * inv_t) |
                        ((u == cu) & (v == cv));
                    const float du = static_cast<float>(u) - uf;
                    const float rank = du * du + dv * dv;
                    float& best_rank = vertex_row[3 * u];
                    const float w = inv_depth;
                    const float tol = tol_a * w * w + tol_b;
                    const bool hit = facing & on_disc;
                    wins = hit &
                           ((w == 0.f) | (inv_t > w + tol) | ((inv_t >= w - tol) & (rank < best_rank)));
                    inv_depth = wins ? inv_t : w;
                    best_rank = wins ? rank : best_rank;
                    if constexpr (kSecond) {
                        float& w2_ref = second_row[3 * u + 2];
                        float& rank2 = second_row[3 * u];
                        const float w2 = w2_ref;
                        const float tol2 = tol_a * w2 * w2 + tol_b;
                        const bool wins2 = hit & ((w2 == 0.f) | (inv_t > w2 + tol2) |
                                                  ((inv_t >= w2 - tol2) & (rank < rank2)));
                        w2_ref = wins2 ? inv_t : w2;
                        rank2 = wins2 ? rank : rank2;
                        second_index_row[u] = wins2 ? index : second_index_row[u];
                    }
                } else {
                    wins = facing & (inv_pz > inv_depth);
                    inv_depth = wins ? inv_pz : inv_depth;
                    if constexpr (kSecond) {
                        float& w2 = second_row[3 * u + 2];
                        const bool wins2 = facing & (inv_pz > w2);
                        w2 = wins2 ? inv_pz : w2;
                        second_index_row[u] = wins2 ? index : second_index_row[u];
                    }
                }
                index_row[u] = wins ? index : index_row[u];
            }
        }
    }

    /// Turns row v's depth and index into vertex, normal and colour.
    void shade(int v, ModelPrediction& out) const {
        const int32_t* index_row = out.index.ptr<int32_t>(v);
        auto* vertex_row = out.vertex.ptr<cv::Vec3f>(v);
        auto* normal_row = out.normal.ptr<cv::Vec3f>(v);
        auto* colour_row = out.colour.ptr<cv::Vec3b>(v);
        for (int u = 0; u < width_; ++u) {
            if (index_row[u] < 0) {
                vertex_row[u] = cv::Vec3f(0.f, 0.f, 0.f);
                normal_row[u] = cv::Vec3f(0.f, 0.f, 0.f);
                colour_row[u] = cv::Vec3b(0, 0, 0);
                continue;
            }
            const Surfel& surfel = surfels_[static_cast<size_t>(index_row[u])];
            if (config_.splat) {
                const float t = 1.f / vertex_row[u][2];
                vertex_row[u] = cv::Vec3f(t * ray_x_[u], t * ray_y_[v], t);
            } else {
                const Eigen::Vector3f p = rotation_ * surfel.position + translation_;
                vertex_row[u] = cv::Vec3f(p.x(), p.y(), p.z());
            }
            const Eigen::Vector3f n = rotation_ * surfel.normal;
            normal_row[u] = cv::Vec3f(n.x(), n.y(), n.z());
            colour_row[u] = cv::Vec3b(to_byte(surfel.colour.x()), to_byte(surfel.colour.y()),
                                      to_byte(surfel.colour.z()));
        }
    }

    const SurfelMap& map_;
    const std::vector<Surfel>& surfels_;
    const int frame_index_;
    const PredictionConfig& config_;
    const int width_, height_;
    const float fx_, fy_, cx_, cy_, f_max_, max_depth_, cos_sq_;
    Eigen::Matrix3f rotation_;  ///< camera_R_world
    Eigen::Vector3f translation_;
    std::vector<float> ray_x_, ray_y_;  ///< pixel ray (x, y, 1) per column and per row
};

}  // namespace

Status SurfelMap::predict_into(const Eigen::Isometry3f& world_T_camera, const io::Intrinsics& k,
                               int width, int height, int frame_index,
                               const PredictionConfig& config, ModelPrediction& out) const {
    DF_RETURN_IF_ERROR(check_prediction_inputs(k, width, height, config));
    out.vertex.create(height, width, CV_32FC3);
    out.normal.create(height, width, CV_32FC3);
    out.colour.create(height, width, CV_8UC3);
    out.index.create(height, width, CV_32SC1);
    const Renderer renderer(*this, world_T_camera, k, width, height, frame_index, config);
    const int threads = detail::resolve_threads(config.threads);
    const int bands = std::max(1, std::min(threads, height / kMinBandRows));
    Layers layers;
    layers.main = &out;
    detail::run_tasks(bands, threads, [&](int b) {
        renderer.render_band(b * height / bands, (b + 1) * height / bands, layers);
    });
    return Status::ok();
}

Status SurfelMap::predict_two_layers(const Eigen::Isometry3f& world_T_camera,
                                     const io::Intrinsics& k, int width, int height,
                                     int frame_index, const PredictionConfig& config,
                                     float second_min_confidence, TwoLayerPrediction& out) const {
    DF_RETURN_IF_ERROR(check_prediction_inputs(k, width, height, config));
    if (!(second_min_confidence >= 0.f)) {
        return error(StatusCode::kInvalidArgument,
                     "SurfelMap::predict_two_layers: second_min_confidence must be >= 0, got " +
                         std::to_string(second_min_confidence));
    }
    out.depth.create(height, width, CV_32FC3);
    out.index.create(height, width, CV_32SC1);
    out.second_depth.create(height, width, CV_32FC3);
    out.second_index.create(height, width, CV_32SC1);
    ModelPrediction main;  // headers only: the band draws into out's images
    main.vertex = out.depth;
    main.index = out.index;
    const Renderer renderer(*this, world_T_camera, k, width, height, frame_index, config);
    const int threads = detail::resolve_threads(config.threads);
    const int bands = std::max(1, std::min(threads, height / kMinBandRows));
    Layers layers;
    layers.main = &main;
    layers.second_depth = &out.second_depth;
    layers.second_index = &out.second_index;
    layers.second_min_confidence = second_min_confidence;
    layers.shade = false;
    detail::run_tasks(bands, threads, [&](int b) {
        renderer.render_band(b * height / bands, (b + 1) * height / bands, layers);
    });
    return Status::ok();
}

Status SurfelMap::refresh_prediction(const std::vector<int32_t>& index_after,
                                     const TwoLayerPrediction& layers,
                                     const Eigen::Isometry3f& world_T_camera,
                                     const io::Intrinsics& k, float min_confidence,
                                     const PredictionConfig& config, ModelPrediction& out) const {
    const int width = layers.index.cols, height = layers.index.rows;
    DF_RETURN_IF_ERROR(check_prediction_inputs(k, width, height, config));
    if (layers.index.type() != CV_32SC1 || layers.second_index.type() != CV_32SC1 ||
        layers.second_index.size() != layers.index.size()) {
        return error(StatusCode::kInvalidArgument,
                     "SurfelMap::refresh_prediction: the index images are not those of "
                     "predict_two_layers (two CV_32SC1 images of one size)");
    }
    out.vertex.create(height, width, CV_32FC3);
    out.normal.create(height, width, CV_32FC3);
    out.colour.create(height, width, CV_8UC3);
    out.index.create(height, width, CV_32SC1);
    const Eigen::Isometry3f camera_T_world = world_T_camera.inverse();
    const Eigen::Matrix3f rotation = camera_T_world.linear();
    const Eigen::Vector3f translation = camera_T_world.translation();
    const float fx = static_cast<float>(k.fx), fy = static_cast<float>(k.fy);
    const float cx = static_cast<float>(k.cx), cy = static_cast<float>(k.cy);
    const auto after = [&](int32_t before) -> int32_t {
        if (before < 0 || static_cast<size_t>(before) >= index_after.size()) return -1;
        const int32_t index = index_after[static_cast<size_t>(before)];
        return index >= 0 && static_cast<size_t>(index) < surfels_.size() ? index : -1;
    };
    const auto refresh_rows = [&](int v_begin, int v_end) {
        for (int v = v_begin; v < v_end; ++v) {
            const int32_t* first_row = layers.index.ptr<int32_t>(v);
            const int32_t* second_row = layers.second_index.ptr<int32_t>(v);
            int32_t* index_row = out.index.ptr<int32_t>(v);
            auto* vertex_row = out.vertex.ptr<cv::Vec3f>(v);
            auto* normal_row = out.normal.ptr<cv::Vec3f>(v);
            auto* colour_row = out.colour.ptr<cv::Vec3b>(v);
            const float y = (static_cast<float>(v) - cy) / fy;
            for (int u = 0; u < width; ++u) {
                const float x = (static_cast<float>(u) - cx) / fx;
                int32_t shown = -1;
                Eigen::Vector3f p, n;
                float t = 0.f;
                // The nearest surfel if it is confident now, else the nearest confident one.
                for (const int32_t candidate : {after(first_row[u]), after(second_row[u])}) {
                    if (candidate < 0) continue;
                    const Surfel& surfel = surfels_[static_cast<size_t>(candidate)];
                    if (!(surfel.confidence >= min_confidence)) continue;
                    p = rotation * surfel.position + translation;
                    n = rotation * surfel.normal;
                    // The ray d = (x, y, 1) meets the plane n.X = n.p at depth n.p / n.d.
                    const float plane = n.dot(p);
                    const float facing = n.x() * x + n.y() * y + n.z();
                    if (!(plane < 0.f && facing < 0.f)) continue;
                    t = plane / facing;
                    shown = candidate;
                    break;
                }
                index_row[u] = shown;
                if (shown < 0) {
                    vertex_row[u] = cv::Vec3f(0.f, 0.f, 0.f);
                    normal_row[u] = cv::Vec3f(0.f, 0.f, 0.f);
                    colour_row[u] = cv::Vec3b(0, 0, 0);
                    continue;
                }
                const Surfel& surfel = surfels_[static_cast<size_t>(shown)];
                vertex_row[u] = config.splat ? cv::Vec3f(t * x, t * y, t)
                                             : cv::Vec3f(p.x(), p.y(), p.z());
                normal_row[u] = cv::Vec3f(n.x(), n.y(), n.z());
                colour_row[u] = cv::Vec3b(to_byte(surfel.colour.x()), to_byte(surfel.colour.y()),
                                          to_byte(surfel.colour.z()));
            }
        }
    };
    const int threads = detail::resolve_threads(config.threads);
    const int bands = std::max(1, std::min(threads, height / kMinBandRows));
    detail::run_tasks(bands, threads, [&](int b) {
        refresh_rows(b * height / bands, (b + 1) * height / bands);
    });
    return Status::ok();
}

Result<ModelPrediction> SurfelMap::predict(const Eigen::Isometry3f& world_T_camera,
                                           const io::Intrinsics& k, int width, int height,
                                           int frame_index, const PredictionConfig& config) const {
    ModelPrediction out;
    DF_RETURN_IF_ERROR(predict_into(world_T_camera, k, width, height, frame_index, config, out));
    return out;
}

}  // namespace df::map
