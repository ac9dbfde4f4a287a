#pragma once
/// Which estimated object is which ground-truth instance: a SLAM run numbers its objects itself
/// (1, 2, 3...), so objects are associated with ground-truth instances by the pixels their masks
/// share over all frames, as a benchmark must. See docs/evaluation.md ("Object maps").
#include <cstddef>
#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <utility>
#include <vector>

#include "core/status.hpp"
#include "eval/segmentation.hpp"

namespace df::eval {

struct ObjectAssociationConfig {
    /// An estimated object matches the instance it shares the most pixels with when those pixels
    /// are at least this fraction of all the object's pixels (over all frames).
    double min_overlap = 0.5;
    /// A rigid instance without an estimated object is "missed" when visible in at least this
    /// many frames (fewer: too brief to expect one).
    size_t min_frames = 5;
};

/// Pixels and frames of one id (an estimated object or a ground-truth instance) over all frames.
struct MaskTotals {
    size_t pixels = 0;
    size_t frames = 0;  ///< frames where the id has at least one pixel
};

/// What an estimated object and an instance share over all frames.
struct MaskPairCounts {
    size_t intersection_px = 0;
    size_t frames = 0;  ///< frames where both have pixels
};

/// Pixel counts per (estimated id, ground-truth id) accumulated over frames.
class MaskOverlap {
  public:
    /// est: CV_16UC1 or CV_8UC1 estimated object ids (0 = none), or empty (no object claimed a
    /// pixel); gt: CV_16UC1 instance ids (0 = none). Same size. `frame` names the frame (files)
    /// in errors.
    Status add_frame(const cv::Mat& est, const cv::Mat& gt, const std::string& frame);

    size_t frames() const { return frames_; }
    const std::map<int, MaskTotals>& estimated() const { return est_; }
    const std::map<int, MaskTotals>& ground_truth() const { return gt_; }
    /// By (estimated id, gt id): pairs that shared a pixel or a frame.
    const std::map<std::pair<int, int>, MaskPairCounts>& pairs() const { return pairs_; }

  private:
    size_t frames_ = 0;
    std::map<int, MaskTotals> est_, gt_;
    std::map<std::pair<int, int>, MaskPairCounts> pairs_;
};

/// An estimated object and a ground-truth instance, with what their masks share over all frames.
struct ObjectPair {
    int est_id = 0;
    int gt_id = 0;
    size_t intersection_px = 0, est_px = 0, gt_px = 0;
    size_t frames = 0;   ///< frames where both have pixels
    double overlap = 0;  ///< intersection_px / est_px
    double iou = 0;      ///< sum of intersections / sum of unions over all frames
};

/// An estimated object that matches no instance, and why.
struct SpuriousObject {
    int est_id = 0;
    size_t est_px = 0;
    int best_gt_id = 0;  ///< the instance sharing most pixels; 0: none
    double overlap = 0;  ///< fraction of the object's pixels on best_gt_id
    std::string reason;
};

struct ObjectAssociation {
    ObjectAssociationConfig config;
    size_t frames = 0;
    std::vector<ObjectPair> matches;     ///< at most one per instance, by gt id
    std::vector<ObjectPair> duplicates;  ///< objects whose instance went to a larger overlap
    std::vector<SpuriousObject> spurious;
    std::vector<int> missed;        ///< rigid gt ids visible in >= min_frames frames, no object
    std::vector<int> not_expected;  ///< rigid gt ids with no object, visible in fewer frames
};

/// Greedy association by largest intersection. Each estimated object (the union of `est_ids`,
/// e.g. those listed in objects.json, and the ids found in the masks) takes the instance it
/// shares the most pixels with (ties: the lower id); it is a candidate when that is at least
/// min_overlap of its pixels and the instance is rigid, else spurious. Candidates by decreasing
/// intersection take their instance if still free, else are duplicates of it. `instances` gives
/// the kinds; an id in the masks that it does not list is never a match.
ObjectAssociation associate_objects(const MaskOverlap& overlap,
                                    const std::vector<GtInstance>& instances,
                                    const std::vector<int>& est_ids,
                                    const ObjectAssociationConfig& config = {});

/// The overlap of RUN_DIR/object_masks/<stamp>.png with SEQ_DIR/instances/<stamp>.png.
struct MaskFolderOverlap {
    MaskOverlap overlap;
    std::vector<GtInstance> instances;  ///< SEQ_DIR/instances.json
    size_t gt_frames = 0;               ///< instances/*.png: every one is a frame
    size_t frames_without_masks = 0;    ///< no object_masks/ file: not processed by the run, not scored
    size_t masks_without_gt = 0;        ///< object_masks/ files with no instances/ namesake
};

/// Accumulates every ground-truth frame; object mask files pair with instance files by exact
/// name. A frame without a mask file counts as all zero (a run writes none when no object claims
/// a pixel). Errors name the file: instances.json, an unreadable PNG, a size or type mismatch, a
/// ground-truth id that instances.json does not list.
Result<MaskFolderOverlap> accumulate_mask_folders(const std::string& sequence_dir,
                                                  const std::string& run_dir);

}  // namespace df::eval
