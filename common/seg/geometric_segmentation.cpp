#include "seg/geometric_segmentation.hpp"

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <vector>

namespace df::seg {
namespace {

inline bool valid_vertex(const float* v) { return v[2] > 0.f && std::isfinite(v[2]); }
inline bool valid_normal(const float* n) { return n[0] != 0.f || n[1] != 0.f || n[2] != 0.f; }

// 255 where the pixel is invalid or any of its 8 neighbours is invalid, across a depth
// discontinuity or across a concave fold.
cv::Mat edge_map(const cv::Mat& vertex, const cv::Mat& normal,
                 const GeometricSegmentationConfig& c) {
    const int w = vertex.cols, h = vertex.rows;
    // Validity once per pixel (each is looked at by 9 pixels).
    cv::Mat ok(vertex.size(), CV_8UC1);
    for (int y = 0; y < h; ++y) {
        const float* v = vertex.ptr<float>(y);
        const float* n = normal.ptr<float>(y);
        uint8_t* o = ok.ptr<uint8_t>(y);
        for (int x = 0; x < w; ++x) o[x] = valid_vertex(v + 3 * x) && valid_normal(n + 3 * x);
    }
    cv::Mat edges(vertex.size(), CV_8UC1, cv::Scalar(255));
    // The 4 direct neighbours first: most edges are found there, and the loop stops early.
    const int dx[8] = {-1, 1, 0, 0, -1, 1, -1, 1};
    const int dy[8] = {0, 0, -1, 1, -1, -1, 1, 1};
    for (int y = 1; y < h - 1; ++y) {
        const float* vrow[3] = {vertex.ptr<float>(y - 1), vertex.ptr<float>(y),
                                vertex.ptr<float>(y + 1)};
        const float* nrow[3] = {normal.ptr<float>(y - 1), normal.ptr<float>(y),
                                normal.ptr<float>(y + 1)};
        const uint8_t* okrow[3] = {ok.ptr<uint8_t>(y - 1), ok.ptr<uint8_t>(y),
                                   ok.ptr<uint8_t>(y + 1)};
        uint8_t* out = edges.ptr<uint8_t>(y);
        for (int x = 1; x < w - 1; ++x) {
            if (!okrow[1][x]) continue;  // stays 255
            // A hole next to the pixel is a boundary: sensors lose depth at silhouettes
            // (shadows, grazing surfaces); re-absorption gives edge pixels back to their
            // segment where depth is continuous.
            if (!(okrow[0][x - 1] & okrow[0][x] & okrow[0][x + 1] & okrow[1][x - 1] &
                  okrow[1][x + 1] & okrow[2][x - 1] & okrow[2][x] & okrow[2][x + 1])) {
                continue;
            }
            const float* v = vrow[1] + 3 * x;
            const float* n = nrow[1] + 3 * x;
            const float z = v[2];
            const float max_d = c.max_distance_m + c.max_distance_per_m2 * z * z;
            const float max_concavity = c.max_concavity + c.max_concavity_per_m2 * z * z;
            bool edge = false;
            for (int k = 0; k < c.neighbours && !edge; ++k) {
                const float* vk = vrow[1 + dy[k]] + 3 * (x + dx[k]);
                const float d =
                    (vk[0] - v[0]) * n[0] + (vk[1] - v[1]) * n[1] + (vk[2] - v[2]) * n[2];
                if (std::fabs(d) > max_d) {
                    edge = true;
                } else if (d >= 0.f) {
                    const float* nk = nrow[1 + dy[k]] + 3 * (x + dx[k]);
                    const float concavity = 1.f - (nk[0] * n[0] + nk[1] * n[1] + nk[2] * n[2]);
                    edge = concavity > max_concavity;
                }
            }
            out[x] = edge ? 255 : 0;
        }
    }
    return edges;
}

// Components below the minimum size become 0; the others are renumbered 1..count.
int drop_small(cv::Mat& labels, const cv::Mat& stats, int components, int min_pixels) {
    std::vector<int32_t> remap(static_cast<size_t>(components), 0);
    int count = 0;
    for (int i = 1; i < components; ++i) {
        if (stats.at<int>(i, cv::CC_STAT_AREA) >= min_pixels)
            remap[static_cast<size_t>(i)] = ++count;
    }
    for (int y = 0; y < labels.rows; ++y) {
        int32_t* l = labels.ptr<int32_t>(y);
        for (int x = 0; x < labels.cols; ++x) l[x] = remap[static_cast<size_t>(l[x])];
    }
    return count;
}

// Re-absorption: in each pass every still unlabelled pixel with valid depth takes the label of
// the 4-neighbour (labelled before the pass) whose depth is nearest, within the tolerance. Only
// the unlabelled pixels are visited.
void absorb(const cv::Mat& vertex, cv::Mat& labels, float max_dz, int passes) {
    const int w = labels.cols, h = labels.rows;
    std::vector<int> todo;
    for (int y = 0; y < h; ++y) {
        const int32_t* l = labels.ptr<int32_t>(y);
        const float* v = vertex.ptr<float>(y);
        for (int x = 0; x < w; ++x) {
            if (l[x] == 0 && valid_vertex(v + 3 * x)) todo.push_back(y * w + x);
        }
    }
    auto* lab = reinterpret_cast<int32_t*>(labels.data);  // continuous (created by OpenCV)
    const auto* vert = reinterpret_cast<const float*>(vertex.data);
    const size_t vstride = vertex.step[0] / sizeof(float);
    std::vector<std::pair<int, int32_t>> updates;
    for (int pass = 0; pass < passes && !todo.empty(); ++pass) {
        updates.clear();
        std::vector<int> still;
        for (int i : todo) {
            const int x = i % w, y = i / w;
            const float z = vert[static_cast<size_t>(y) * vstride + 3 * x + 2];
            float best = max_dz;
            int32_t label = 0;
            const int nx[4] = {x - 1, x + 1, x, x};
            const int ny[4] = {y, y, y - 1, y + 1};
            for (int k = 0; k < 4; ++k) {
                if (nx[k] < 0 || nx[k] >= w || ny[k] < 0 || ny[k] >= h) continue;
                const int32_t nl = lab[ny[k] * w + nx[k]];
                if (nl == 0) continue;
                const float dz =
                    std::fabs(vert[static_cast<size_t>(ny[k]) * vstride + 3 * nx[k] + 2] - z);
                if (dz < best) {
                    best = dz;
                    label = nl;
                }
            }
            if (label != 0) {
                updates.emplace_back(i, label);
            } else {
                still.push_back(i);
            }
        }
        for (const auto& [i, label] : updates) lab[i] = label;  // after the pass: no bias
        todo.swap(still);
    }
}

}  // namespace

std::string validate(const GeometricSegmentationConfig& c) {
    if (std::string e = params::check(c); !e.empty()) return e;  // ranges: geoseg.proto
    if (c.neighbours != 4 && c.neighbours != 8)
        return "neighbours must be 4 or 8, got " + std::to_string(c.neighbours);
    return "";
}

Result<GeometricSegmentation> segment_geometry(const cv::Mat& vertex, const cv::Mat& normal,
                                               const GeometricSegmentationConfig& config) {
    if (std::string bad = validate(config); !bad.empty()) {
        return error(StatusCode::kInvalidArgument, "GeometricSegmentationConfig: " + bad);
    }
    if (vertex.empty() || vertex.type() != CV_32FC3 || normal.type() != CV_32FC3 ||
        normal.size() != vertex.size()) {
        return error(StatusCode::kInvalidArgument,
                     "segment_geometry: vertex and normal must be CV_32FC3 of one size, got " +
                         cv::typeToString(vertex.type()) + " " + std::to_string(vertex.cols) + "x" +
                         std::to_string(vertex.rows) + " and " + cv::typeToString(normal.type()) +
                         " " + std::to_string(normal.cols) + "x" + std::to_string(normal.rows));
    }
    GeometricSegmentation out;
    out.edges = edge_map(vertex, normal, config);
    cv::Mat stats, centroids;
    const int components =
        cv::connectedComponentsWithStats(out.edges == 0, out.labels, stats, centroids, 4, CV_32S);
    out.count = drop_small(out.labels, stats, components, config.min_segment_pixels);
    absorb(vertex, out.labels, config.absorb_max_depth_difference_m, config.absorb_iterations);
    return out;
}

}  // namespace df::seg
