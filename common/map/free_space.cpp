// The map's removals: free-space violations (surfels a frame sees through) and clean() of old
// unstable surfels, both compacting the surfel array.
#include <algorithm>
#include <cmath>
#include <opencv2/core/utility.hpp>

#include "map/surfel_map.hpp"

namespace df::map {

void SurfelMap::remove_free_space(const cv::Mat& vertex_map_cam, const cv::Mat& mask,
                                  const Eigen::Isometry3f& camera_T_world, const io::Intrinsics& k,
                                  int frame_index, size_t existing, FusionStats& stats,
                                  bool keep_stable, std::vector<int32_t>* index_after) {
    const int width = vertex_map_cam.cols;
    const int height = vertex_map_cam.rows;
    // Measured depth per pixel, 0 where the frame proves nothing (invalid or masked).
    measured_depth_.resize(static_cast<size_t>(width) * height);
    cv::parallel_for_(cv::Range(0, height), [&](const cv::Range& rows) {
        for (int v = rows.start; v < rows.end; ++v) {
            const auto* vertex_row = vertex_map_cam.ptr<cv::Vec3f>(v);
            const uint8_t* mask_row = mask.empty() ? nullptr : mask.ptr<uint8_t>(v);
            float* depth_row = measured_depth_.data() + static_cast<size_t>(v) * width;
            for (int u = 0; u < width; ++u) {
                const cv::Vec3f& p = vertex_row[u];
                const bool valid = (mask_row == nullptr || mask_row[u] == 0) &&
                                   std::isfinite(p[0]) && std::isfinite(p[1]) &&
                                   std::isfinite(p[2]) && p[2] > 0.f;
                depth_row[u] = valid ? p[2] : 0.f;
            }
        }
    });
    const Eigen::Matrix3f rotation = camera_T_world.linear();
    const Eigen::Vector3f translation = camera_T_world.translation();
    const float fx = static_cast<float>(k.fx), fy = static_cast<float>(k.fy);
    const float cx = static_cast<float>(k.cx), cy = static_cast<float>(k.cy);
    const int window = std::max(0, config_.free_space_window_px);
    remove_flags_.assign(existing, 0);
    // Each surfel is tested on its own (it is weakened or flagged, nothing else is written), so
    // blocks of surfels run in parallel; only the counts are summed.
    struct Counts {
        size_t flagged = 0, weakened = 0;
    };
    const size_t block_size = 16384;
    const int blocks = static_cast<int>((existing + block_size - 1) / block_size);
    std::vector<Counts> block_counts(static_cast<size_t>(blocks));
    cv::parallel_for_(cv::Range(0, blocks), [&](const cv::Range& range) {
        for (int b = range.start; b < range.end; ++b) {
            Counts& counts = block_counts[static_cast<size_t>(b)];
            const size_t end = std::min(existing, (static_cast<size_t>(b) + 1) * block_size);
            for (size_t i = static_cast<size_t>(b) * block_size; i < end; ++i) {
                Surfel& s = surfels_[i];
                if (!is_active(s, frame_index) || (keep_stable && is_stable(s))) continue;
                const Eigen::Vector3f p = rotation * s.position + translation;
                if (!(p.z() > 0.f)) continue;
                const float uf = std::floor(fx * p.x() / p.z() + cx + 0.5f);
                const float vf = std::floor(fy * p.y() / p.z() + cy + 0.5f);
                // The whole window must lie in the image (also rejects NaN).
                if (!(uf >= static_cast<float>(window) && vf >= static_cast<float>(window) &&
                      uf < static_cast<float>(width - window) &&
                      vf < static_cast<float>(height - window))) {
                    continue;
                }
                const int u = static_cast<int>(uf);
                const int v = static_cast<int>(vf);
                const float margin = std::max(config_.free_space_margin_m,
                                              config_.free_space_margin_per_m2 * p.z() * p.z()) +
                                     s.radius;
                // Measured depth must exceed this at every pixel of the window (0 = no evidence
                // fails).
                const float behind = p.z() + margin;
                if (!(measured_depth_[static_cast<size_t>(v) * width + u] > behind)) continue;
                bool seen_through = true;
                for (int y = v - window; y <= v + window && seen_through; ++y) {
                    const float* row = measured_depth_.data() + static_cast<size_t>(y) * width;
                    for (int x = u - window; x <= u + window; ++x) {
                        if (!(row[x] > behind)) {
                            seen_through = false;
                            break;
                        }
                    }
                }
                if (!seen_through) continue;
                if (is_stable(s)) {
                    s.confidence -= config_.free_space_penalty * weight_u_[static_cast<size_t>(u)] *
                                    weight_v_[static_cast<size_t>(v)];
                    ++counts.weakened;
                } else {
                    remove_flags_[i] = 1;
                    ++counts.flagged;
                }
            }
        }
    });
    size_t flagged = 0;
    for (const Counts& counts : block_counts) {
        flagged += counts.flagged;
        stats.weakened_free_space += counts.weakened;
    }
    if (flagged == 0) return;
    compact([&](size_t i) { return i >= existing || remove_flags_[i] == 0; }, index_after);
    stats.removed_free_space = flagged;
}

template <class Keep>
size_t SurfelMap::compact(const Keep& keep, std::vector<int32_t>* index_after) {
    if (index_after != nullptr) moved_to_.assign(surfels_.size(), -1);
    size_t kept = 0;
    for (size_t i = 0; i < surfels_.size(); ++i) {
        if (!keep(i)) continue;
        if (index_after != nullptr) moved_to_[i] = static_cast<int32_t>(kept);
        if (kept != i) surfels_[kept] = surfels_[i];
        ++kept;
    }
    const size_t removed = surfels_.size() - kept;
    surfels_.resize(kept);
    if (index_after != nullptr && removed > 0) {
        for (int32_t& index : *index_after) {
            if (index >= 0) index = moved_to_[static_cast<size_t>(index)];
        }
    }
    return removed;
}

size_t SurfelMap::clean(int frame_index, std::vector<int32_t>* index_after) {
    return compact(
        [&](size_t i) {
            const Surfel& s = surfels_[i];
            return is_stable(s) ||
                   frame_index - s.last_seen_frame <= config_.unstable_max_unseen_frames;
        },
        index_after);
}

}  // namespace df::map
