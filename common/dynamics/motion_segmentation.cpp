#include "dynamics/motion_segmentation.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <vector>

namespace df::dynamics {

namespace {

std::string describe(const cv::Mat& m) {
    return m.empty() ? std::string("empty")
                     : cv::typeToString(m.type()) + " " + std::to_string(m.cols) + "x" +
                           std::to_string(m.rows);
}

std::string check_inputs(const MotionInput& in) {
    const cv::Size size = in.residual_m.size();
    const auto bad = [&](const char* name, const cv::Mat& m, int type, bool optional) {
        if (optional && m.empty()) return std::string();
        if (m.type() == type && m.size() == size) return std::string();
        return std::string(name) + " must be " + cv::typeToString(type) + " " +
               std::to_string(size.width) + "x" + std::to_string(size.height) + ", got " +
               describe(m);
    };
    if (in.residual_m.empty() || in.residual_m.type() != CV_32F)
        return "residual_m must be CV_32FC1, got " + describe(in.residual_m);
    for (const std::string& e :
         {bad("depth_m", in.depth_m, CV_32F, false), bad("excluded", in.excluded, CV_8UC1, true),
          bad("geometric", in.geometric, CV_32SC1, true), bad("carried", in.carried, CV_8UC1, true),
          bad("photometric", in.photometric, CV_32F, true),
          bad("history", in.history, CV_8UC1, true)})
        if (!e.empty()) return e;
    if (in.geometric_count < 0) return "geometric_count must be >= 0";
    return "";
}

/// A mask made on demand (MotionInput's *_source): empty, or CV_8UC1 of the residual's size.
std::string check_lazy(const char* name, const cv::Mat& m, cv::Size size) {
    if (m.empty() || (m.type() == CV_8UC1 && m.size() == size)) return "";
    return std::string(name) + " must be CV_8UC1 " + std::to_string(size.width) + "x" +
           std::to_string(size.height) + ", got " + describe(m);
}

/// Whether a segment or region that is dynamic by its residual is still by its history:
/// `seen` of its `size` pixels have evidence, `moved` of them were seen through.
bool still(int size, int seen, int moved, const MotionSegmentationConfig& c) {
    return c.history_frames > 0 && seen > 0 &&
           static_cast<float>(seen) >= c.history_min_seen * static_cast<float>(size) &&
           static_cast<float>(moved) <= c.history_max_moved * static_cast<float>(seen);
}

/// Whole intensity levels of |intensity - model intensity| (photometric_threshold's median).
constexpr size_t kPhotometricBins = 257;

/// max(min_photometric, photometric_spread_factor x the median intensity residual of the pixels
/// not left out), the median from a histogram of whole intensity levels (`bins`, `n` values).
float photometric_threshold(const std::vector<int>& bins, int n,
                            const MotionSegmentationConfig& c) {
    if (c.photometric_spread_factor <= 0.f || n == 0) return c.min_photometric;
    int below = 0;
    size_t median = 0;
    while (median < bins.size() && 2 * (below + bins[median]) < n) below += bins[median++];
    // The median level's centre: residuals in [k, k + 1) count as k + 0.5.
    const float spread = c.photometric_spread_factor * (static_cast<float>(median) + 0.5f);
    return std::max(c.min_photometric, spread);
}

/// Runs body(first_row, end_row, accumulator) over row blocks in parallel, each block with its
/// own copy of `init`, and returns the accumulators in block order. Every accumulator here holds
/// integer counts, so what the caller sums does not depend on the threads.
template <class Acc, class Body>
std::vector<Acc> over_row_blocks(int rows, const Acc& init, const Body& body) {
    const int blocks = std::min(rows, 8);
    std::vector<Acc> acc(static_cast<size_t>(blocks), init);
    cv::parallel_for_(cv::Range(0, blocks), [&](const cv::Range& r) {
        for (int b = r.start; b < r.end; ++b)
            body(rows * b / blocks, rows * (b + 1) / blocks, acc[static_cast<size_t>(b)]);
    });
    return acc;
}

/// Element-wise sum of `from` into `into` (same size).
void add_counts(const std::vector<int>& from, std::vector<int>& into) {
    for (size_t i = 0; i < into.size(); ++i) into[i] += from[i];
}

}  // namespace

std::string validate(const MotionSegmentationConfig& c) { return params::check(c); }

Result<MotionResult> segment_motion(const MotionInput& in, const MotionSegmentationConfig& c) {
    if (std::string e = validate(c); !e.empty())
        return error(StatusCode::kInvalidArgument, "MotionSegmentationConfig: " + e);
    if (std::string e = check_inputs(in); !e.empty())
        return error(StatusCode::kInvalidArgument, "motion segmentation: " + e);
    const int rows = in.residual_m.rows, cols = in.residual_m.cols;
    MotionResult out;
    out.mask = cv::Mat::zeros(rows, cols, CV_8UC1);
    // 0. Free space of an older frame that this one fills (its pixels count as dynamic).
    cv::Mat filled;
    if (c.free_space_filled && in.filled_source) {
        cv::Mat candidates = cv::Mat::ones(rows, cols, CV_8UC1);
        if (!in.excluded.empty()) candidates.setTo(0, in.excluded);
        filled = in.filled_source(candidates);
        if (std::string e = check_lazy("filled", filled, in.residual_m.size()); !e.empty())
            return error(StatusCode::kInvalidArgument, "motion segmentation: " + e);
    }
    out.filled_pixels = filled.empty() ? 0 : cv::countNonZero(filled);
    const bool any_filled =
        out.filled_pixels >= std::min(c.min_segment_pixels, c.min_region_pixels);

    const uint8_t* no_mask = nullptr;
    const auto excluded_row = [&](int y) {
        return in.excluded.empty() ? no_mask : in.excluded.ptr<uint8_t>(y);
    };
    const cv::Mat* photo =
        (c.min_photometric > 0.f && !in.photometric.empty()) ? &in.photometric : nullptr;

    // 1. Cluster the clipped residuals of the pixels not already left out (and histogram the
    // intensity residuals for the photometric threshold), row blocks in parallel.
    struct Spread {
        Histogram residual;
        std::vector<int> photo_bins;
        int photo_n = 0;
    };
    const Spread no_spread{Histogram(c.max_residual_m, 256),
                           std::vector<int>(photo ? kPhotometricBins : 0, 0), 0};
    std::vector<Spread> spreads =
        over_row_blocks(rows, no_spread, [&](int y0, int y1, Spread& acc) {
            for (int y = y0; y < y1; ++y) {
                const float* r = in.residual_m.ptr<float>(y);
                const float* p = photo ? photo->ptr<float>(y) : nullptr;
                const uint8_t* ex = excluded_row(y);
                for (int x = 0; x < cols; ++x) {
                    if (ex && ex[x]) continue;
                    if (std::isfinite(r[x])) acc.residual.add(std::fabs(r[x]));
                    if (p && std::isfinite(p[x])) {
                        ++acc.photo_bins[static_cast<size_t>(
                            std::clamp(std::fabs(p[x]), 0.f, 256.f))];
                        ++acc.photo_n;
                    }
                }
            }
        });
    Spread spread = no_spread;
    for (const Spread& b : spreads) {
        spread.residual.add(b.residual);
        add_counts(b.photo_bins, spread.photo_bins);
        spread.photo_n += b.photo_n;
    }
    out.residual_pixels = spread.residual.count();
    out.clusters = spread.residual.two_means();
    const bool residual_motion =
        out.residual_pixels > 0 && out.clusters.high - out.clusters.low >= c.min_centroid_gap_m;
    if (!residual_motion && !any_filled) return out;

    // 2. Dynamic pixels: in the high cluster and above the noise at their depth; with them each
    // geometric segment's counts, and the region candidates outside every segment.
    const bool with_segments = !in.geometric.empty() && in.geometric_count > 0;
    const size_t segment_count = with_segments ? static_cast<size_t>(in.geometric_count) + 1 : 1;
    if (photo != nullptr)
        out.photometric_threshold = photometric_threshold(spread.photo_bins, spread.photo_n, c);
    // The whole frame's residuals rising together are a pose slightly off, not a mover: a
    // pixel must also stand out of the frame's own spread.
    out.frame_floor_m = c.residual_spread_factor > 0.f
                            ? c.residual_spread_factor * spread.residual.quantile(0.5f)
                            : 0.f;
    const float frame_floor_m = out.frame_floor_m;
    cv::Mat dynamic(rows, cols, CV_8UC1);
    cv::Mat candidate(rows, cols, CV_8UC1);
    struct SegmentCounts {
        int dynamic = 0;
        std::vector<int> size, with_residual, dyn, geometric_dyn;
    };
    const std::vector<int> zeros(with_segments ? segment_count : 0, 0);
    const SegmentCounts no_counts{0, zeros, zeros, zeros, zeros};
    std::vector<SegmentCounts> blocks =
        over_row_blocks(rows, no_counts, [&](int y0, int y1, SegmentCounts& acc) {
            for (int y = y0; y < y1; ++y) {
                const float* r = in.residual_m.ptr<float>(y);
                const float* z = in.depth_m.ptr<float>(y);
                const float* p = photo ? photo->ptr<float>(y) : nullptr;
                const int* g = with_segments ? in.geometric.ptr<int>(y) : nullptr;
                const uint8_t* ex = excluded_row(y);
                const uint8_t* f = filled.empty() ? nullptr : filled.ptr<uint8_t>(y);
                uint8_t* d = dynamic.ptr<uint8_t>(y);
                uint8_t* cand = candidate.ptr<uint8_t>(y);
                for (int x = 0; x < cols; ++x) {
                    uint8_t v = 0;
                    const bool out_of_play = ex && ex[x];
                    const bool fills = !out_of_play && f && f[x];
                    if (fills) {
                        v = 255;
                        ++acc.dynamic;
                    } else if (!out_of_play && std::isfinite(r[x])) {
                        const float a = std::min(std::fabs(r[x]), c.max_residual_m);
                        const float floor_m = std::max(
                            frame_floor_m, c.min_residual_m + c.min_residual_per_m2 * z[x] * z[x]);
                        if (residual_motion && a > out.clusters.threshold && a > floor_m) {
                            v = 255;
                            ++acc.dynamic;
                        } else if (p && std::isfinite(p[x]) && p[x] > out.photometric_threshold) {
                            v = 128;  // evidence only
                        } else if (a > c.region_grow_fraction * floor_m) {
                            v = 64;  // weak: grows a region, never counts as a segment's evidence
                        }
                    }
                    d[x] = v;
                    const size_t s = g ? static_cast<size_t>(g[x]) : 0;
                    cand[x] = (v != 0 && s == 0) ? 255 : 0;
                    if (s == 0 || out_of_play) continue;
                    ++acc.size[s];
                    acc.with_residual[s] += (fills || std::isfinite(r[x])) ? 1 : 0;
                    acc.dyn[s] += (v == 255 || v == 128) ? 1 : 0;
                    acc.geometric_dyn[s] += v == 255 ? 1 : 0;
                }
            }
        });
    SegmentCounts counts = no_counts;
    for (const SegmentCounts& b : blocks) {
        counts.dynamic += b.dynamic;
        add_counts(b.size, counts.size);
        add_counts(b.with_residual, counts.with_residual);
        add_counts(b.dyn, counts.dyn);
        add_counts(b.geometric_dyn, counts.geometric_dyn);
    }
    out.dynamic_pixels = counts.dynamic;
    if (out.dynamic_pixels == 0 ||
        static_cast<float>(out.dynamic_pixels) <
            c.min_dynamic_fraction * static_cast<float>(out.residual_pixels))
        return out;

    // 3. Grow to whole objects: candidate segments with enough evidence ...
    std::vector<int> size(segment_count, 0);
    std::vector<uint8_t> segment_candidate(segment_count, 0);
    if (with_segments) {
        size = counts.size;
        // Segments whose evidence passes one of the two fractions and not the other: only for
        // them does it matter whether the previous frame's motion covered them.
        std::vector<uint8_t> undecided(segment_count, 0);
        bool any_undecided = false;
        for (size_t s = 1; s < segment_count; ++s) {
            if (counts.geometric_dyn[s] < c.min_segment_pixels || counts.with_residual[s] == 0)
                continue;
            const float dyn = static_cast<float>(counts.dyn[s]);
            const float with_residual = static_cast<float>(counts.with_residual[s]);
            undecided[s] = (dyn >= c.carried_segment_fraction * with_residual) !=
                           (dyn >= c.min_segment_fraction * with_residual);
            any_undecided = any_undecided || undecided[s];
        }
        // The previous frame's motion, warped here, made only now that it counts, and only on
        // the undecided segments.
        cv::Mat carried_mask = in.carried;
        if (carried_mask.empty() && in.carried_source && any_undecided) {
            cv::Mat needed(rows, cols, CV_8UC1);
            cv::parallel_for_(cv::Range(0, rows), [&](const cv::Range& block) {
                for (int y = block.start; y < block.end; ++y) {
                    const int* g = in.geometric.ptr<int>(y);
                    uint8_t* n = needed.ptr<uint8_t>(y);
                    for (int x = 0; x < cols; ++x) n[x] = undecided[static_cast<size_t>(g[x])];
                }
            });
            carried_mask = in.carried_source(needed);
        }
        if (std::string e = check_lazy("carried", carried_mask, in.residual_m.size()); !e.empty())
            return error(StatusCode::kInvalidArgument, "motion segmentation: " + e);
        std::vector<int> carried(segment_count, 0);
        if (!carried_mask.empty() && any_undecided) {
            const std::vector<std::vector<int>> carried_blocks =
                over_row_blocks(rows, std::vector<int>(segment_count, 0),
                                [&](int y0, int y1, std::vector<int>& acc) {
                                    for (int y = y0; y < y1; ++y) {
                                        const int* g = in.geometric.ptr<int>(y);
                                        const uint8_t* cm = carried_mask.ptr<uint8_t>(y);
                                        const uint8_t* ex = excluded_row(y);
                                        for (int x = 0; x < cols; ++x)
                                            if (g[x] != 0 && cm[x] && !(ex && ex[x]))
                                                ++acc[static_cast<size_t>(g[x])];
                                    }
                                });
            for (const std::vector<int>& b : carried_blocks) add_counts(b, carried);
        }
        for (size_t s = 1; s < segment_count; ++s) {
            if (counts.geometric_dyn[s] < c.min_segment_pixels || counts.with_residual[s] == 0)
                continue;
            const bool was_dynamic =
                size[s] > 0 &&
                static_cast<float>(carried[s]) >= c.carry_min_overlap * static_cast<float>(size[s]);
            const float need = was_dynamic ? c.carried_segment_fraction : c.min_segment_fraction;
            if (static_cast<float>(counts.dyn[s]) <
                need * static_cast<float>(counts.with_residual[s]))
                continue;
            segment_candidate[s] = 1;
        }
    }
    // ... and, outside every segment (far or small things the segmentation left unlabelled, or
    // everything when no segments came), connected regions of dynamic and weak pixels
    // (hysteresis) with at least min_region_pixels dynamic ones.
    cv::Mat labels, stats, centroids;
    const size_t region_count = static_cast<size_t>(
        cv::connectedComponentsWithStats(candidate, labels, stats, centroids, 8));
    std::vector<uint8_t> region_candidate(region_count, 0);
    {
        std::vector<int> strong(region_count, 0);
        const std::vector<std::vector<int>> strong_blocks = over_row_blocks(
            rows, std::vector<int>(region_count, 0), [&](int y0, int y1, std::vector<int>& acc) {
                for (int y = y0; y < y1; ++y) {
                    const int* l = labels.ptr<int>(y);
                    const uint8_t* d = dynamic.ptr<uint8_t>(y);
                    for (int x = 0; x < cols; ++x)
                        if (d[x] == 255) ++acc[static_cast<size_t>(l[x])];
                }
            });
        for (const std::vector<int>& b : strong_blocks) add_counts(b, strong);
        for (size_t k = 1; k < region_count; ++k)
            region_candidate[k] = strong[k] >= c.min_region_pixels ? 1 : 0;
    }
    const bool any_candidate =
        std::find(segment_candidate.begin(), segment_candidate.end(), 1) !=
            segment_candidate.end() ||
        std::find(region_candidate.begin(), region_candidate.end(), 1) != region_candidate.end();
    if (!any_candidate) return out;

    // 4. Free-space evidence from an older frame (made only when a candidate needs it): a
    // candidate the old frame saw where it is now, never through, is still.
    cv::Mat history = in.history;
    if (history.empty() && in.history_source && c.history_frames > 0) {
        cv::Mat needed(rows, cols, CV_8UC1);
        cv::parallel_for_(cv::Range(0, rows), [&](const cv::Range& block) {
            for (int y = block.start; y < block.end; ++y) {
                const int* g = with_segments ? in.geometric.ptr<int>(y) : nullptr;
                const int* l = labels.ptr<int>(y);
                const uint8_t* ex = excluded_row(y);
                uint8_t* n = needed.ptr<uint8_t>(y);
                for (int x = 0; x < cols; ++x) {
                    const bool segment =
                        g && segment_candidate[static_cast<size_t>(g[x])] && !(ex && ex[x]);
                    n[x] = (segment || region_candidate[static_cast<size_t>(l[x])]) ? 1 : 0;
                }
            }
        });
        history = in.history_source(needed);
    }
    if (std::string e = check_lazy("history", history, in.residual_m.size()); !e.empty())
        return error(StatusCode::kInvalidArgument, "motion segmentation: " + e);
    std::vector<int> segment_seen(segment_count, 0), segment_moved(segment_count, 0);
    std::vector<int> region_seen(region_count, 0), region_moved(region_count, 0);
    if (!history.empty()) {
        struct Evidence {
            std::vector<int> segment_seen, segment_moved, region_seen, region_moved;
        };
        const Evidence none{segment_seen, segment_moved, region_seen, region_moved};
        const std::vector<Evidence> evidence =
            over_row_blocks(rows, none, [&](int y0, int y1, Evidence& acc) {
                for (int y = y0; y < y1; ++y) {
                    const int* g = with_segments ? in.geometric.ptr<int>(y) : nullptr;
                    const int* l = labels.ptr<int>(y);
                    const uint8_t* ex = excluded_row(y);
                    const uint8_t* h = history.ptr<uint8_t>(y);
                    for (int x = 0; x < cols; ++x) {
                        if (h[x] == kNoEvidence) continue;
                        const int moved = h[x] == kMoved ? 1 : 0;
                        const size_t s = g ? static_cast<size_t>(g[x]) : 0;
                        if (s != 0 && segment_candidate[s] && !(ex && ex[x])) {
                            ++acc.segment_seen[s];
                            acc.segment_moved[s] += moved;
                        }
                        const size_t k = static_cast<size_t>(l[x]);
                        if (region_candidate[k]) {
                            ++acc.region_seen[k];
                            acc.region_moved[k] += moved;
                        }
                    }
                }
            });
        for (const Evidence& b : evidence) {
            add_counts(b.segment_seen, segment_seen);
            add_counts(b.segment_moved, segment_moved);
            add_counts(b.region_seen, region_seen);
            add_counts(b.region_moved, region_moved);
        }
    }
    std::vector<uint8_t> take_segment(segment_count, 0), take_region(region_count, 0);
    for (size_t s = 1; s < segment_count; ++s) {
        if (!segment_candidate[s]) continue;
        if (still(size[s], segment_seen[s], segment_moved[s], c)) {
            ++out.still_segments;
            continue;
        }
        take_segment[s] = 1;
        ++out.segments;
    }
    for (size_t k = 1; k < region_count; ++k) {
        if (!region_candidate[k]) continue;
        const int area = stats.at<int>(static_cast<int>(k), cv::CC_STAT_AREA);
        if (still(area, region_seen[k], region_moved[k], c)) {
            ++out.still_segments;
            continue;
        }
        take_region[k] = 1;
        ++out.segments;
    }
    cv::parallel_for_(cv::Range(0, rows), [&](const cv::Range& block) {
        for (int y = block.start; y < block.end; ++y) {
            const int* g = with_segments ? in.geometric.ptr<int>(y) : nullptr;
            const int* l = labels.ptr<int>(y);
            const uint8_t* ex = excluded_row(y);
            uint8_t* m = out.mask.ptr<uint8_t>(y);
            for (int x = 0; x < cols; ++x) {
                const bool segment = g && take_segment[static_cast<size_t>(g[x])] && !(ex && ex[x]);
                if (segment || take_region[static_cast<size_t>(l[x])]) m[x] = 255;
            }
        }
    });
    if (c.dilate_px > 0 && out.segments > 0) {
        const int k = 2 * c.dilate_px + 1;
        cv::dilate(out.mask, out.mask, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(k, k)));
        if (!in.excluded.empty()) out.mask.setTo(0, in.excluded);
    }
    out.mask_pixels = cv::countNonZero(out.mask);
    out.moving = out.mask_pixels > 0;
    return out;
}

}  // namespace df::dynamics
