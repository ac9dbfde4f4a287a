// Per-frame matching of predicted segments to ground-truth instances, and its accumulation.
#include "eval/segmentation.hpp"

#include <algorithm>
#include <map>
#include <unordered_map>

namespace df::eval {

const char* to_string(InstanceKind kind) {
    switch (kind) {
        case InstanceKind::kRigid:
            return "rigid";
        case InstanceKind::kNonRigid:
            return "non_rigid";
        case InstanceKind::kUnknown:
            return "unknown";
    }
    return "unknown";
}

namespace {

double ratio(double num, size_t den) { return den ? num / static_cast<double>(den) : 0.0; }

/// The mean figures of an instance's or a kind's sums (both kinds of score carry the same four).
template <typename Sums, typename Score>
void fill_means(const Sums& s, Score* out) {
    out->mean_iou = ratio(s.iou, s.visible);
    out->mean_precision = ratio(s.precision, s.matched);
    out->mean_recall = ratio(s.recall, s.visible);
    out->detection_recall = ratio(static_cast<double>(s.matched), s.visible);
}

struct Overlaps {
    std::map<int, size_t> gt_px, pred_px;         // by id / label (0 excluded)
    std::map<std::pair<int, int>, size_t> joint;  // (gt id, pred label), both non-zero
};

template <typename PredT>
void count_overlaps(const cv::Mat& gt, const cv::Mat& pred, Overlaps* o) {
    std::unordered_map<uint32_t, size_t> joint;  // key: gt << 16 | pred, 0s included
    for (int r = 0; r < gt.rows; ++r) {
        const uint16_t* g = gt.ptr<uint16_t>(r);
        const PredT* p = pred.empty() ? nullptr : pred.ptr<PredT>(r);
        uint32_t run_key = 0;
        size_t run = 0;
        for (int c = 0; c < gt.cols; ++c) {
            const uint32_t key = (uint32_t{g[c]} << 16) | (p ? uint32_t{p[c]} : 0u);
            if (run > 0 && key != run_key) {  // label images come in runs: count them at once
                joint[run_key] += run;
                run = 0;
            }
            run_key = key;
            ++run;
        }
        if (run > 0) joint[run_key] += run;
    }
    for (const auto& [key, n] : joint) {
        const int g = static_cast<int>(key >> 16), p = static_cast<int>(key & 0xffff);
        if (g) o->gt_px[g] += n;
        if (p) o->pred_px[p] += n;
        if (g && p) o->joint[{g, p}] += n;
    }
}

}  // namespace

Result<FrameMatches> match_frame(const cv::Mat& gt, const cv::Mat& pred, double match_iou) {
    if (gt.type() != CV_16UC1) {
        return error(StatusCode::kInvalidArgument, "ground-truth instance image is not 16-bit");
    }
    if (!pred.empty() && pred.type() != CV_16UC1 && pred.type() != CV_8UC1) {
        return error(StatusCode::kInvalidArgument,
                     "predicted mask is not a single-channel 8- or 16-bit image");
    }
    if (!pred.empty() && pred.size() != gt.size()) {
        return error(StatusCode::kInvalidArgument,
                     "predicted mask is " + std::to_string(pred.cols) + "x" +
                         std::to_string(pred.rows) + ", ground truth is " +
                         std::to_string(gt.cols) + "x" + std::to_string(gt.rows));
    }
    Overlaps o;
    if (!pred.empty() && pred.type() == CV_8UC1) {
        count_overlaps<uint8_t>(gt, pred, &o);
    } else {
        count_overlaps<uint16_t>(gt, pred, &o);
    }
    struct Candidate {
        double iou;
        int gt, pred;
        size_t inter;
    };
    std::vector<Candidate> candidates;
    for (const auto& [ids, inter] : o.joint) {
        const size_t uni = o.gt_px[ids.first] + o.pred_px[ids.second] - inter;
        const double iou = static_cast<double>(inter) / static_cast<double>(uni);
        if (iou >= match_iou) candidates.push_back({iou, ids.first, ids.second, inter});
    }
    std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
        if (a.iou != b.iou) return a.iou > b.iou;
        return a.gt != b.gt ? a.gt < b.gt : a.pred < b.pred;
    });
    std::map<int, Candidate> by_gt;
    std::map<int, bool> pred_taken;
    for (const Candidate& c : candidates) {
        if (by_gt.count(c.gt) || pred_taken[c.pred]) continue;
        by_gt.emplace(c.gt, c);
        pred_taken[c.pred] = true;
    }
    FrameMatches frame;
    for (const auto& [id, px] : o.gt_px) {
        InstanceMatch m;
        m.gt_id = id;
        m.gt_px = px;
        const auto it = by_gt.find(id);
        if (it != by_gt.end()) {
            m.pred_label = it->second.pred;
            m.iou = it->second.iou;
            m.intersection_px = it->second.inter;
            m.pred_px = o.pred_px[m.pred_label];
        }
        frame.instances.push_back(m);
    }
    frame.predicted_segments = o.pred_px.size();
    frame.unmatched_segments = o.pred_px.size() - by_gt.size();
    return frame;
}

SegmentationScorer::SegmentationScorer(std::vector<GtInstance> instances, SegmentationConfig config)
    : instances_(std::move(instances)), config_(config), sums_(instances_.size()) {}

Status SegmentationScorer::add_frame(const cv::Mat& gt, const cv::Mat& pred,
                                     const std::string& frame) {
    auto matches = match_frame(gt, pred, config_.match_iou);
    if (!matches) return matches.status().with_context(frame);
    for (const InstanceMatch& m : matches->instances) {
        const auto it = std::find_if(instances_.begin(), instances_.end(),
                                     [&](const GtInstance& i) { return i.id == m.gt_id; });
        if (it == instances_.end()) {
            return error(StatusCode::kInvalidArgument, frame + ": ground-truth instance id " +
                                                           std::to_string(m.gt_id) +
                                                           " is not listed in instances.json");
        }
        Sums& s = sums_[static_cast<size_t>(it - instances_.begin())];
        ++s.visible;
        if (m.pred_label) {
            ++s.matched;
            s.iou += m.iou;
            s.precision += static_cast<double>(m.intersection_px) / static_cast<double>(m.pred_px);
            s.recall += static_cast<double>(m.intersection_px) / static_cast<double>(m.gt_px);
        }
    }
    ++frames_;
    segments_ += matches->predicted_segments;
    false_positives_ += matches->unmatched_segments;
    return Status::ok();
}

SegmentationResult SegmentationScorer::result() const {
    SegmentationResult r;
    r.match_iou = config_.match_iou;
    r.frames = frames_;
    r.frames_without_prediction = missing_;
    r.predictions_without_gt = unpaired_;
    r.predicted_segments = segments_;
    r.false_positive_segments = false_positives_;
    const char* kind_names[] = {"rigid", "non_rigid", "unknown", "all"};
    std::vector<Sums> kind_sums(4);
    std::vector<size_t> kind_instances(4, 0);
    for (size_t i = 0; i < instances_.size(); ++i) {
        const Sums& s = sums_[i];
        if (s.visible == 0) continue;
        InstanceScore score;
        score.instance = instances_[i];
        score.frames_visible = s.visible;
        score.frames_matched = s.matched;
        fill_means(s, &score);
        r.instances.push_back(score);
        for (size_t k : {static_cast<size_t>(instances_[i].kind), size_t{3}}) {
            Sums& ks = kind_sums[k];
            ks.visible += s.visible;
            ks.matched += s.matched;
            ks.iou += s.iou;
            ks.precision += s.precision;
            ks.recall += s.recall;
            ++kind_instances[k];
        }
    }
    std::sort(r.instances.begin(), r.instances.end(),
              [](const InstanceScore& a, const InstanceScore& b) {
                  return a.instance.id < b.instance.id;
              });
    for (size_t k = 0; k < 4; ++k) {
        const Sums& ks = kind_sums[k];
        KindSummary summary;
        summary.kind = kind_names[k];
        summary.instances = kind_instances[k];
        summary.visible = ks.visible;
        summary.matched = ks.matched;
        fill_means(ks, &summary);
        r.kinds.push_back(summary);
    }
    r.detection_recall = r.kinds.back().detection_recall;
    r.detection_precision = ratio(static_cast<double>(segments_ - false_positives_), segments_);
    return r;
}

}  // namespace df::eval
