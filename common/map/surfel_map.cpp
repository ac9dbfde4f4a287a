#include "map/surfel_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

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
                    const cv::Mat& mask, const cv::Mat& index_map, const PinholeIntrinsics& k) {
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
    if (!(k.fx > 0.f) || !(k.fy > 0.f)) {
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

void SurfelMap::project_active(const Eigen::Isometry3f& camera_T_world, const PinholeIntrinsics& k,
                               int width, int height, int frame_index) {
    const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
    zbuffer_index_.assign(pixels, -1);
    zbuffer_depth_.assign(pixels, std::numeric_limits<float>::infinity());
    const Eigen::Matrix3f rotation = camera_T_world.linear();
    const Eigen::Vector3f translation = camera_T_world.translation();
    for (size_t i = 0; i < surfels_.size(); ++i) {
        const Surfel& s = surfels_[i];
        if (!is_active(s, frame_index)) continue;
        const Eigen::Vector3f p = rotation * s.position + translation;
        if (!(p.z() > 0.f)) continue;
        // A surfel seen from its back must not hide the surface in front of it.
        if ((rotation * s.normal).dot(p) > 0.f) continue;
        const float u = std::floor(k.fx * p.x() / p.z() + k.cx + 0.5f);
        const float v = std::floor(k.fy * p.y() / p.z() + k.cy + 0.5f);
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

Result<FusionStats> SurfelMap::fuse(const cv::Mat& vertex_map_cam, const cv::Mat& normal_map_cam,
                                    const cv::Mat& rgb, const cv::Mat& mask,
                                    const cv::Mat& index_map,
                                    const Eigen::Isometry3f& world_T_camera,
                                    const PinholeIntrinsics& intrinsics, int frame_index) {
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
    const float half_diagonal_px =
        0.5f * std::sqrt(static_cast<float>(width * width + height * height));
    const float weight_scale = -1.f / (2.f * config_.confidence_sigma * config_.confidence_sigma *
                                       half_diagonal_px * half_diagonal_px);
    // exp(a (du^2 + dv^2)) = exp(a du^2) exp(a dv^2): width + height exponentials a frame.
    weight_u_.resize(static_cast<size_t>(width));
    weight_v_.resize(static_cast<size_t>(height));
    for (int u = 0; u < width; ++u) {
        const float du = static_cast<float>(u) - intrinsics.cx;
        weight_u_[static_cast<size_t>(u)] = std::exp(du * du * weight_scale);
    }
    for (int v = 0; v < height; ++v) {
        const float dv = static_cast<float>(v) - intrinsics.cy;
        weight_v_[static_cast<size_t>(v)] = std::exp(dv * dv * weight_scale);
    }
    const float radius_scale = std::sqrt(2.f) * 2.f / (intrinsics.fx + intrinsics.fy);
    const float min_normal_dot = std::cos(config_.max_normal_angle_rad);
    const size_t existing = surfels_.size();
    // Grow geometrically, never past the capacity, so that creation does not reallocate a frame.
    const size_t worst_case =
        std::min(config_.max_surfels, existing + static_cast<size_t>(width) * height);
    if (surfels_.capacity() < worst_case) {
        surfels_.reserve(std::min(config_.max_surfels, std::max(worst_case, 2 * existing)));
    }

    FusionStats stats;
    for (int v = 0; v < height; ++v) {
        const auto* vertex_row = vertex_map_cam.ptr<cv::Vec3f>(v);
        const auto* normal_row = normal_map_cam.ptr<cv::Vec3f>(v);
        const auto* rgb_row = rgb.ptr<cv::Vec3b>(v);
        const uint8_t* mask_row = mask.empty() ? nullptr : mask.ptr<uint8_t>(v);
        const int32_t* index_row = use_index_map ? index_map.ptr<int32_t>(v) : nullptr;
        for (int u = 0; u < width; ++u) {
            if (mask_row != nullptr && mask_row[u] != 0) continue;
            const cv::Vec3f& vc = vertex_row[u];
            const cv::Vec3f& nc = normal_row[u];
            if (!finite3(vc) || !(vc[2] > 0.f) || !finite3(nc)) continue;
            if (nc[0] == 0.f && nc[1] == 0.f && nc[2] == 0.f) continue;

            const float weight =
                weight_u_[static_cast<size_t>(u)] * weight_v_[static_cast<size_t>(v)];
            const float radius =
                vc[2] * radius_scale / std::max(std::abs(nc[2]), config_.min_abs_normal_z);
            const Eigen::Vector3f position =
                world_R_camera * Eigen::Vector3f(vc[0], vc[1], vc[2]) + world_t_camera;
            const Eigen::Vector3f normal =
                (world_R_camera * Eigen::Vector3f(nc[0], nc[1], nc[2])).normalized();
            const cv::Vec3b& c = rgb_row[u];
            const Eigen::Vector3f colour(c[0], c[1], c[2]);

            const int32_t candidate =
                use_index_map ? index_row[u] : zbuffer_index_[static_cast<size_t>(v) * width + u];
            if (candidate >= 0 && static_cast<size_t>(candidate) < existing) {
                Surfel& s = surfels_[static_cast<size_t>(candidate)];
                const float surfel_z = camera_R_world.row(2).dot(s.position) + camera_t_world.z();
                if (std::abs(surfel_z - vc[2]) < config_.max_depth_difference_m &&
                    s.normal.dot(normal) > min_normal_dot) {
                    const float sum = s.confidence + weight;
                    if (radius < config_.merge_radius_factor * s.radius) {
                        const float a = s.confidence / sum;
                        const float b = weight / sum;
                        s.position = a * s.position + b * position;
                        s.normal = (a * s.normal + b * normal).normalized();
                        s.colour = a * s.colour + b * colour;
                        s.radius = a * s.radius + b * radius;
                    }
                    s.confidence = sum;
                    s.last_seen_frame = frame_index;
                    ++stats.fused;
                    continue;
                }
            }
            if (surfels_.size() >= config_.max_surfels) {
                ++stats.rejected_by_capacity;
                continue;
            }
            surfels_.push_back(
                Surfel{position, normal, colour, radius, weight, frame_index, frame_index});
            ++stats.created;
        }
    }
    total_rejected_by_capacity_ += stats.rejected_by_capacity;
    stats.removed = clean(frame_index);
    stats.total = surfels_.size();
    stats.stable = stable_count();
    return stats;
}

size_t SurfelMap::clean(int frame_index) {
    const auto end = std::remove_if(surfels_.begin(), surfels_.end(), [&](const Surfel& s) {
        return !is_stable(s) && frame_index - s.init_frame > config_.unstable_max_age_frames;
    });
    const auto removed = static_cast<size_t>(surfels_.end() - end);
    surfels_.erase(end, surfels_.end());
    return removed;
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
