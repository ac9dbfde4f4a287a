#include "map/surfel_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/core/utility.hpp>

#include "io/ply/ply.hpp"

namespace df::map {
namespace {

Status check_image(const cv::Mat& image, const char* name, int type, const cv::Size& size) {
    if (image.type() != type || image.size() != size) {
        return error(StatusCode::kInvalidArgument,
                     std::string("SurfelMap::fuse: ") + name + " must be " +
                         cv::typeToString(type) + " " + std::to_string(size.width) + "x" +
                         std::to_string(size.height) + ", got " + cv::typeToString(image.type()) +
                         " " + std::to_string(image.cols) + "x" + std::to_string(image.rows));
    }
    return Status::ok();
}

Status check_inputs(const cv::Mat& vertex, const cv::Mat& normal, const cv::Mat& rgb,
                    const cv::Mat& mask, const cv::Mat& index_map, const io::Intrinsics& k) {
    if (vertex.empty() || vertex.type() != CV_32FC3) {
        return error(StatusCode::kInvalidArgument,
                     "SurfelMap::fuse: vertex_map_cam must be a non-empty CV_32FC3 image, got " +
                         cv::typeToString(vertex.type()) + " " + std::to_string(vertex.cols) + "x" +
                         std::to_string(vertex.rows));
    }
    const cv::Size size = vertex.size();
    DF_RETURN_IF_ERROR(check_image(normal, "normal_map_cam", CV_32FC3, size));
    DF_RETURN_IF_ERROR(check_image(rgb, "rgb", CV_8UC3, size));
    if (!mask.empty()) DF_RETURN_IF_ERROR(check_image(mask, "mask", CV_8UC1, size));
    if (!index_map.empty()) DF_RETURN_IF_ERROR(check_image(index_map, "index_map", CV_32SC1, size));
    if (!(k.fx > 0.0) || !(k.fy > 0.0) || !std::isfinite(k.fx) || !std::isfinite(k.fy)) {
        return error(StatusCode::kInvalidArgument,
                     "SurfelMap::fuse: focal lengths must be positive, got fx=" +
                         std::to_string(k.fx) + " fy=" + std::to_string(k.fy));
    }
    return Status::ok();
}

bool finite3(const cv::Vec3f& v) {
    return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

}  // namespace

SurfelMap::SurfelMap(SurfelMapConfig config) : config_(config) {}

Status SurfelMap::restore(std::vector<Surfel> surfels, uint64_t total_rejected_by_capacity) {
    if (surfels.size() > config_.max_surfels) {
        return error(StatusCode::kInvalidArgument,
                     std::to_string(surfels.size()) + " surfels exceed max_surfels " +
                         std::to_string(config_.max_surfels));
    }
    for (size_t i = 0; i < surfels.size(); ++i) {
        const Surfel& s = surfels[i];
        if (!s.position.allFinite() || !s.normal.allFinite() || !std::isfinite(s.radius) ||
            !std::isfinite(s.confidence)) {
            return error(StatusCode::kInvalidArgument,
                         "surfel " + std::to_string(i) + " has a non-finite field");
        }
    }
    surfels_ = std::move(surfels);
    total_rejected_by_capacity_ = total_rejected_by_capacity;
    return Status::ok();
}

size_t SurfelMap::stable_count() const {
    return static_cast<size_t>(std::count_if(surfels_.begin(), surfels_.end(),
                                             [this](const Surfel& s) { return is_stable(s); }));
}

std::vector<size_t> SurfelMap::active(int frame_index) const {
    std::vector<size_t> indices;
    for (size_t i = 0; i < surfels_.size(); ++i) {
        if (is_active(surfels_[i], frame_index)) indices.push_back(i);
    }
    return indices;
}

void SurfelMap::project_active(const Eigen::Isometry3f& camera_T_world, const io::Intrinsics& k,
                               int width, int height, int frame_index) {
    const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
    zbuffer_index_.assign(pixels, -1);
    zbuffer_depth_.assign(pixels, std::numeric_limits<float>::infinity());
    const Eigen::Matrix3f rotation = camera_T_world.linear();
    const Eigen::Vector3f translation = camera_T_world.translation();
    const float fx = static_cast<float>(k.fx), fy = static_cast<float>(k.fy);
    const float cx = static_cast<float>(k.cx), cy = static_cast<float>(k.cy);
    for (size_t i = 0; i < surfels_.size(); ++i) {
        const Surfel& s = surfels_[i];
        if (!is_active(s, frame_index)) continue;
        const Eigen::Vector3f p = rotation * s.position + translation;
        if (!(p.z() > 0.f)) continue;
        // A surfel seen from its back must not hide the surface in front of it.
        if ((rotation * s.normal).dot(p) > 0.f) continue;
        const float u = std::floor(fx * p.x() / p.z() + cx + 0.5f);
        const float v = std::floor(fy * p.y() / p.z() + cy + 0.5f);
        if (!(u >= 0.f && v >= 0.f && u < static_cast<float>(width) &&
              v < static_cast<float>(height))) {
            continue;
        }
        const size_t pixel =
            static_cast<size_t>(v) * static_cast<size_t>(width) + static_cast<size_t>(u);
        if (p.z() < zbuffer_depth_[pixel]) {
            zbuffer_depth_[pixel] = p.z();
            zbuffer_index_[pixel] = static_cast<int32_t>(i);
        }
    }
}

void SurfelMap::prepare_weights(int width, int height, const io::Intrinsics& intrinsics,
                                const cv::Size& sensor_size) {
    const cv::Size whole = sensor_size.empty() ? cv::Size(width, height) : sensor_size;
    const float half_diagonal_px = 0.5f * std::sqrt(static_cast<float>(
                                              whole.width * whole.width + whole.height * whole.height));
    const float weight_scale = -1.f / (2.f * config_.confidence_sigma * config_.confidence_sigma *
                                       half_diagonal_px * half_diagonal_px);
    // exp(a (du^2 + dv^2)) = exp(a du^2) exp(a dv^2): width + height exponentials a frame.
    weight_u_.resize(static_cast<size_t>(width));
    weight_v_.resize(static_cast<size_t>(height));
    for (int u = 0; u < width; ++u) {
        const float du = static_cast<float>(u) - static_cast<float>(intrinsics.cx);
        weight_u_[static_cast<size_t>(u)] = std::exp(du * du * weight_scale);
    }
    for (int v = 0; v < height; ++v) {
        const float dv = static_cast<float>(v) - static_cast<float>(intrinsics.cy);
        weight_v_[static_cast<size_t>(v)] = std::exp(dv * dv * weight_scale);
    }
}

Result<FusionStats> SurfelMap::carve(const cv::Mat& vertex_map_cam, const cv::Mat& mask,
                                     const Eigen::Isometry3f& world_T_camera,
                                     const io::Intrinsics& intrinsics, int frame_index,
                                     bool keep_stable, const cv::Size& sensor_size) {
    DF_RETURN_IF_ERROR(check_image(vertex_map_cam, "vertex map", CV_32FC3, vertex_map_cam.size()));
    if (!mask.empty()) DF_RETURN_IF_ERROR(check_image(mask, "mask", CV_8UC1, vertex_map_cam.size()));
    if (!(intrinsics.fx > 0) || !(intrinsics.fy > 0)) {
        return error(StatusCode::kInvalidArgument, "carve: focal lengths must be positive");
    }
    FusionStats stats;
    if (config_.remove_free_space) {
        prepare_weights(vertex_map_cam.cols, vertex_map_cam.rows, intrinsics, sensor_size);
        remove_free_space(vertex_map_cam, mask, world_T_camera.inverse(), intrinsics, frame_index,
                          surfels_.size(), stats, keep_stable);
    }
    stats.removed = clean(frame_index);
    stats.total = surfels_.size();
    stats.stable = stable_count();
    return stats;
}

Result<FusionStats> SurfelMap::fuse(const cv::Mat& vertex_map_cam, const cv::Mat& normal_map_cam,
                                    const cv::Mat& rgb, const cv::Mat& mask,
                                    const cv::Mat& index_map,
                                    const Eigen::Isometry3f& world_T_camera,
                                    const io::Intrinsics& intrinsics, int frame_index,
                                    const FuseOptions& options) {
    DF_RETURN_IF_ERROR(
        check_inputs(vertex_map_cam, normal_map_cam, rgb, mask, index_map, intrinsics));
    const int width = vertex_map_cam.cols;
    const int height = vertex_map_cam.rows;
    const Eigen::Isometry3f camera_T_world = world_T_camera.inverse();
    const bool use_index_map = !index_map.empty();
    if (!use_index_map) project_active(camera_T_world, intrinsics, width, height, frame_index);

    const Eigen::Matrix3f world_R_camera = world_T_camera.linear();
    const Eigen::Vector3f world_t_camera = world_T_camera.translation();
    const Eigen::Matrix3f camera_R_world = camera_T_world.linear();
    const Eigen::Vector3f camera_t_world = camera_T_world.translation();
    prepare_weights(width, height, intrinsics, options.sensor_size);
    const float radius_scale =
        std::sqrt(2.f) * 2.f / static_cast<float>(intrinsics.fx + intrinsics.fy);
    const float min_normal_dot = std::cos(config_.max_normal_angle_rad);
    const size_t existing = surfels_.size();
    // Grow geometrically, never past the capacity, so that creation does not reallocate a frame.
    const size_t worst_case =
        std::min(config_.max_surfels, existing + static_cast<size_t>(width) * height);
    if (surfels_.capacity() < worst_case) {
        surfels_.reserve(std::min(config_.max_surfels, std::max(worst_case, 2 * existing)));
    }

    FusionStats stats;
    const float fx = static_cast<float>(intrinsics.fx), fy = static_cast<float>(intrinsics.fy);
    const float cx = static_cast<float>(intrinsics.cx), cy = static_cast<float>(intrinsics.cy);
    auto candidate_at = [&](int u, int v) {
        return use_index_map ? index_map.ptr<int32_t>(v)[u]
                             : zbuffer_index_[static_cast<size_t>(v) * width + u];
    };
    const auto valid_pixel = [&](int u, int v) {
        if (!mask.empty() && mask.ptr<uint8_t>(v)[u] != 0) return false;
        const cv::Vec3f& vc = vertex_map_cam.ptr<cv::Vec3f>(v)[u];
        const cv::Vec3f& nc = normal_map_cam.ptr<cv::Vec3f>(v)[u];
        return finite3(vc) && vc[2] > 0.f && finite3(nc) &&
               !(nc[0] == 0.f && nc[1] == 0.f && nc[2] == 0.f);
    };
    // Association (ElasticFusion searches a window of its super-sampled index map): each pixel
    // looks at the surfels shown in the (2 w + 1)^2 window around it and takes, among those
    // within the depth and normal gates, the one whose projected centre is nearest the pixel.
    // A pixel with a surfel of the window within the depth gate but none within both gates sees
    // known surface with a disagreeing normal: it is neither fused nor made a new surfel (new
    // surfels would pile up as duplicate layers wherever normals are noisy).
    const int window = std::max(0, config_.association_window_px);
    const size_t pixels = static_cast<size_t>(width) * height;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    shown_.resize(pixels);
    cv::parallel_for_(cv::Range(0, height), [&](const cv::Range& rows) {
        for (int v = rows.start; v < rows.end; ++v) {
            for (int u = 0; u < width; ++u) {
                Shown& shown = shown_[static_cast<size_t>(v) * width + u];
                const int32_t c = candidate_at(u, v);
                if (c < 0 || static_cast<size_t>(c) >= existing) {
                    shown.depth = nan;
                    continue;
                }
                const Surfel& s = surfels_[static_cast<size_t>(c)];
                const Eigen::Vector3f p = camera_R_world * s.position + camera_t_world;
                shown.depth = p.z();
                shown.u = fx * p.x() / p.z() + cx;
                shown.v = fy * p.y() / p.z() + cy;
                shown.normal = s.normal;
            }
        }
    });
    pixel_candidate_.resize(pixels);
    pixel_distance_.resize(pixels);
    cv::parallel_for_(cv::Range(0, height), [&](const cv::Range& rows) {
        for (int v = rows.start; v < rows.end; ++v) {
            for (int u = 0; u < width; ++u) {
                if (!valid_pixel(u, v)) {
                    const size_t pixel = static_cast<size_t>(v) * width + u;
                    pixel_candidate_[pixel] = kInvalidPixel;
                    pixel_distance_[pixel] = std::numeric_limits<float>::infinity();
                    continue;
                }
                const cv::Vec3f& vc = vertex_map_cam.ptr<cv::Vec3f>(v)[u];
                const cv::Vec3f& nc = normal_map_cam.ptr<cv::Vec3f>(v)[u];
                const Eigen::Vector3f normal =
                    world_R_camera * Eigen::Vector3f(nc[0], nc[1], nc[2]);
                int32_t best = kNoCandidate;
                float best_d2 = std::numeric_limits<float>::infinity();
                bool surface_near = false;
                int32_t last = -1;
                for (int y = std::max(0, v - window); y <= std::min(height - 1, v + window); ++y) {
                    for (int x = std::max(0, u - window); x <= std::min(width - 1, u + window);
                         ++x) {
                        const int32_t c = candidate_at(x, y);
                        if (c < 0 || static_cast<size_t>(c) >= existing || c == last) continue;
                        last = c;
                        const Shown& s = shown_[static_cast<size_t>(y) * width + x];
                        if (!(s.depth > 0.f) ||
                            !(std::abs(s.depth - vc[2]) < config_.max_depth_difference_m)) {
                            continue;
                        }
                        surface_near = true;
                        if (!(s.normal.dot(normal) > min_normal_dot)) continue;
                        const float du = s.u - static_cast<float>(u);
                        const float dv = s.v - static_cast<float>(v);
                        const float d2 = du * du + dv * dv;
                        if (d2 < best_d2) {
                            best_d2 = d2;
                            best = c;
                        }
                    }
                }
                const size_t pixel = static_cast<size_t>(v) * width + u;
                pixel_candidate_[pixel] = best >= 0 ? best : (surface_near ? kKnownSurface
                                                                           : kNoCandidate);
                pixel_distance_[pixel] = best_d2;
            }
        }
    });
    // One observation per surfel per frame (as ElasticFusion's update pass): when several
    // pixels choose the same surfel, the pixel nearest the surfel's projected centre updates
    // it; the others neither update it nor duplicate it. Without this a surfel would average in
    // a whole disc of pixels each frame, its confidence would grow many times faster than it
    // was observed, and its position would wander.
    owner_pixel_.assign(existing, -1);
    owner_distance_.assign(existing, std::numeric_limits<float>::infinity());
    for (size_t pixel = 0; pixel < pixels; ++pixel) {
        const int32_t c = pixel_candidate_[pixel];
        if (c < 0) continue;
        if (pixel_distance_[pixel] < owner_distance_[static_cast<size_t>(c)]) {
            owner_distance_[static_cast<size_t>(c)] = pixel_distance_[pixel];
            owner_pixel_[static_cast<size_t>(c)] = static_cast<int32_t>(pixel);
        }
    }
    // The observation a pixel makes, in the world.
    struct Observation {
        Eigen::Vector3f position, normal, colour;
        float weight, radius;
    };
    const auto observe = [&](int u, int v) {
        const cv::Vec3f& vc = vertex_map_cam.ptr<cv::Vec3f>(v)[u];
        const cv::Vec3f& nc = normal_map_cam.ptr<cv::Vec3f>(v)[u];
        const cv::Vec3b& c = rgb.ptr<cv::Vec3b>(v)[u];
        Observation o;
        o.weight = weight_u_[static_cast<size_t>(u)] * weight_v_[static_cast<size_t>(v)];
        o.radius = vc[2] * radius_scale / std::max(std::abs(nc[2]), config_.min_abs_normal_z);
        o.position = world_R_camera * Eigen::Vector3f(vc[0], vc[1], vc[2]) + world_t_camera;
        o.normal = (world_R_camera * Eigen::Vector3f(nc[0], nc[1], nc[2])).normalized();
        o.colour = Eigen::Vector3f(c[0], c[1], c[2]);
        return o;
    };
    // Updates first, in parallel: each surfel has one owner pixel, so no two pixels write the
    // same surfel, and the new surfels come after the existing ones.
    struct UpdateCounts {
        size_t known_surface = 0, covered = 0, fused = 0;
    };
    const int blocks = std::min(height, 8);
    std::vector<UpdateCounts> block_counts(static_cast<size_t>(std::max(blocks, 0)));
    cv::parallel_for_(cv::Range(0, blocks), [&](const cv::Range& range) {
        for (int b = range.start; b < range.end; ++b) {
            UpdateCounts& counts = block_counts[static_cast<size_t>(b)];
            for (int v = height * b / blocks; v < height * (b + 1) / blocks; ++v) {
                for (int u = 0; u < width; ++u) {
                    const size_t pixel = static_cast<size_t>(v) * width + u;
                    const int32_t candidate = pixel_candidate_[pixel];
                    if (candidate == kKnownSurface) {
                        ++counts.known_surface;
                        continue;
                    }
                    if (candidate < 0) continue;
                    if (owner_pixel_[static_cast<size_t>(candidate)] !=
                        static_cast<int32_t>(pixel)) {
                        ++counts.covered;
                        continue;
                    }
                    const Observation o = observe(u, v);
                    Surfel& s = surfels_[static_cast<size_t>(candidate)];
                    const float sum = s.confidence + o.weight;
                    if (o.radius < config_.merge_radius_factor * s.radius) {
                        const float a = s.confidence / sum;
                        const float w = o.weight / sum;
                        s.position = a * s.position + w * o.position;
                        s.normal = (a * s.normal + w * o.normal).normalized();
                        s.colour = a * s.colour + w * o.colour;
                        s.radius = a * s.radius + w * o.radius;
                    }
                    s.confidence = sum;
                    s.last_seen_frame = frame_index;
                    ++counts.fused;
                }
            }
        }
    });
    for (const UpdateCounts& counts : block_counts) {
        stats.known_surface += counts.known_surface;
        stats.covered += counts.covered;
        stats.fused += counts.fused;
    }
    // Then the new surfels, in pixel order (their indices do not depend on the threads).
    for (int v = 0; v < height; ++v) {
        for (int u = 0; u < width; ++u) {
            const size_t pixel = static_cast<size_t>(v) * width + u;
            if (pixel_candidate_[pixel] != kNoCandidate) continue;
            if (!options.create_surfels) {
                ++stats.not_created;
                continue;
            }
            if (surfels_.size() >= config_.max_surfels) {
                ++stats.rejected_by_capacity;
                continue;
            }
            const Observation o = observe(u, v);
            surfels_.push_back(Surfel{o.position, o.normal, o.colour, o.radius, o.weight,
                                      frame_index, frame_index});
            ++stats.created;
        }
    }
    total_rejected_by_capacity_ += stats.rejected_by_capacity;
    std::vector<int32_t>* index_after = options.index_after;
    if (index_after != nullptr) {
        index_after->resize(existing);
        for (size_t i = 0; i < existing; ++i) (*index_after)[i] = static_cast<int32_t>(i);
    }
    if (config_.remove_free_space) {
        remove_free_space(vertex_map_cam, mask, camera_T_world, intrinsics, frame_index, existing,
                          stats, false, index_after);
    }
    stats.removed = clean(frame_index, index_after);
    stats.total = surfels_.size();
    stats.stable = stable_count();
    return stats;
}

Status SurfelMap::write_ply(const std::string& file, bool stable_only) const {
    io::PointCloud cloud;
    std::vector<float> radius;
    std::vector<float> confidence;
    for (const Surfel& s : surfels_) {
        if (stable_only && !is_stable(s)) continue;
        cloud.positions.push_back(s.position.cast<double>());
        cloud.normals.push_back(s.normal);
        const Eigen::Vector3f rgb = s.colour.array().round().max(0.f).min(255.f);
        cloud.colours.push_back(rgb.cast<uint8_t>());
        radius.push_back(s.radius);
        confidence.push_back(s.confidence);
    }
    cloud.add_scalar("radius") = std::move(radius);
    cloud.add_scalar("confidence") = std::move(confidence);
    return io::write_ply(file, cloud).with_context("SurfelMap::write_ply");
}

}  // namespace df::map
