#pragma once
/// The surfel map of ElasticFusion-style SLAM: a set of oriented discs (surfels) in the world
/// frame and the rules that fuse a camera frame into it. Plain matrices in, plain structs out:
/// it knows nothing of tracking, preprocessing or DDS.
///
/// Conventions:
/// - Camera frame: x right, y down, z forward (optical axis), metres. World frame: metres.
/// - A surfel normal points towards the cameras that saw it (as the input normal maps do).
/// - Storage is an array of structs (one `Surfel`, 52 bytes, per element): fusion touches every
///   field of a surfel at once, so the fields of one surfel are best kept in one cache line.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/status.hpp"
#include "io/rgbd_image.hpp"
#include "params/slam_params.hpp"

namespace df::map {

/// One oriented disc of the map.
struct Surfel {
    Eigen::Vector3f position;  ///< world frame, metres
    Eigen::Vector3f normal;    ///< world frame, unit length, towards the observing cameras
    Eigen::Vector3f colour;    ///< red, green, blue, 0..255 (float so that averaging is exact)
    float radius = 0.f;        ///< disc radius, metres
    float confidence = 0.f;    ///< sum of the weights of the observations fused into it
    int init_frame = 0;        ///< frame index that created it
    int last_seen_frame = 0;   ///< last frame index that fused an observation into it
};

/// Fusion parameters; defaults are those of ElasticFusion (FACTS.md §5).
/// Its fields (defaults, ranges, units, meanings) are declared once, in
/// common/config/slam.proto (SlamParams.Map), and generated into params/slam_params.hpp.
using SurfelMapConfig = params::slam::Map;

/// What the map looks like from a camera (SurfelMap::predict). All images width x height.
struct ModelPrediction {
    cv::Mat vertex;  ///< CV_32FC3, camera frame, metres; (0,0,0) where no surfel is seen
    cv::Mat normal;  ///< CV_32FC3, camera frame, unit, towards the camera; (0,0,0) where none
    cv::Mat colour;  ///< CV_8UC3 R,G,B; (0,0,0) where none
    cv::Mat index;   ///< CV_32SC1, index into surfels() of the surfel seen, -1 where none;
                     ///< valid until the map next changes
};

/// SurfelMap::predict_two_layers' index images (CV_32SC1, -1 where none) and the depth buffers
/// they were drawn with; kept by the caller so that its buffers are reused frame to frame.
struct TwoLayerPrediction {
    cv::Mat index;         ///< the nearest surfel of every surfel drawn (predict()'s index)
    cv::Mat second_index;  ///< the nearest of those with confidence >= second_min_confidence
    cv::Mat depth, second_depth;  ///< scratch (inverse depth and rank while drawing)
};

/// How SurfelMap::predict renders.
/// Its fields (defaults, ranges, units, meanings) are declared once, in
/// common/config/slam.proto (SlamParams.Prediction), and generated into params/slam_params.hpp.
struct PredictionConfig : params::slam::Prediction {
    /// Only surfels with at least this confidence are rendered (0 = every surfel). Not a
    /// parameter: the system sets it (system.predict_min_confidence; 0 for object maps).
    float min_confidence = 0.f;
};

/// What one call of fuse() did.
struct FusionStats {
    size_t fused = 0;                 ///< observations merged into an existing surfel
    /// observations with a surfel of their window within the depth gate but none within the
    /// normal gate as well: neither fused nor created (noisy normals on known surface)
    size_t known_surface = 0;
    /// observations of a surfel already updated by a pixel nearer its centre this frame (one
    /// update per surfel and frame); neither fused nor created
    size_t covered = 0;
    size_t created = 0;               ///< new surfels
    size_t not_created = 0;           ///< observations with no surfel, left alone (no creation)
    size_t removed = 0;               ///< surfels removed by clean() (unstable and old)
    size_t removed_free_space = 0;    ///< unstable surfels removed as free-space violations
    size_t weakened_free_space = 0;   ///< stable surfels that lost confidence for one
                                      ///< (they may then go in the same call's clean())
    size_t rejected_by_capacity = 0;  ///< observations dropped because the map was full
    size_t total = 0;                 ///< surfels in the map afterwards
    size_t stable = 0;                ///< stable surfels in the map afterwards
};

/// How fuse() treats one frame.
struct FuseOptions {
    /// false: pixels with no surfel to fuse into are left alone (FusionStats::not_created): the
    /// frame only confirms what the map has.
    bool create_surfels = true;
    /// The whole sensor image's size when the images are a crop of it (their intrinsics shifted
    /// to match): an observation's weight depends on its distance from the principal point
    /// against half of *this* image's diagonal, so a pixel weighs the same in a crop as in the
    /// whole frame. Empty: the images are the whole sensor image.
    cv::Size sensor_size;
    /// Not null: filled with, per surfel index before the call, its index after it (-1 for a
    /// surfel the call removed), so that an index image of the map before fusion (the
    /// association rendering) can be brought up to date (SurfelMap::refresh_prediction).
    std::vector<int32_t>* index_after = nullptr;
};

class SurfelMap {
  public:
    explicit SurfelMap(SurfelMapConfig config = {});

    /// Fuses one frame into the map, then calls clean(frame_index).
    /// - vertex_map_cam: CV_32FC3, camera frame, metres; a pixel is invalid if not finite or
    ///   z <= 0.
    /// - normal_map_cam: CV_32FC3, camera frame, unit, towards the camera; invalid if not finite
    ///   or (0,0,0).
    /// - rgb: CV_8UC3 in R,G,B channel order.
    /// - mask: empty, or CV_8UC1 where non-zero means "leave this pixel out" (e.g. people).
    /// - index_map: empty, or CV_32SC1 with the index of the surfel the model prediction sees at
    ///   each pixel (-1 for none), valid for the map as it is before this call. If empty, the
    ///   active surfels are projected with world_T_camera into a z-buffer of their indices.
    /// - frame_index: increasing frame counter (the time of the surfels).
    /// All images have the same size. A pixel is fused into its associated surfel if both
    /// association gates pass, otherwise it creates a surfel (if there is room). Then the
    /// free-space violations are handled (see SurfelMapConfig::remove_free_space).
    /// kInvalidArgument naming the bad input for wrong types or sizes or non-positive focal
    /// lengths; the map is not changed then. Surfel indices change (compaction) on every call.
    Result<FusionStats> fuse(const cv::Mat& vertex_map_cam, const cv::Mat& normal_map_cam,
                             const cv::Mat& rgb, const cv::Mat& mask, const cv::Mat& index_map,
                             const Eigen::Isometry3f& world_T_camera,
                             const io::Intrinsics& intrinsics, int frame_index,
                             const FuseOptions& options = {});

    /// The free-space pass of fuse() alone, with no fusion: the active surfels the frame sees
    /// through (SurfelMapConfig::remove_free_space) are weakened or removed, then clean(). For
    /// a map none of the frame's pixels were fused into (an object map whose object moved
    /// away). Inputs as fuse(); `mask` non-zero = the pixel proves nothing.
    /// `keep_stable`: only unstable surfels go (for a pose that is a guess: a stable model is
    /// not eroded by it).
    Result<FusionStats> carve(const cv::Mat& vertex_map_cam, const cv::Mat& mask,
                              const Eigen::Isometry3f& world_T_camera,
                              const io::Intrinsics& intrinsics, int frame_index,
                              bool keep_stable = false, const cv::Size& sensor_size = {});

    /// Removes unstable surfels not fused for more than config.unstable_max_unseen_frames
    /// (relative to frame_index); returns how many were removed. Keeps the order of the others.
    size_t clean(int frame_index) { return clean(frame_index, nullptr); }

    /// Renders the map from a camera: the active surfels (is_active at frame_index) that face
    /// the camera and pass config's filters, nearest first per pixel (see PredictionConfig).
    /// world_T_camera: camera pose in the world, metres. k: pinhole intrinsics, pixels (pixel
    /// centres at integer coordinates). Images are width x height. Runs on config.threads
    /// threads; the result is identical for any thread count. Thread-safe (const, no shared
    /// scratch). kInvalidArgument for sizes outside 1..32767, non-positive or non-finite
    /// intrinsics, or config values outside their documented ranges.
    Result<ModelPrediction> predict(const Eigen::Isometry3f& world_T_camera,
                                    const io::Intrinsics& k, int width, int height, int frame_index,
                                    const PredictionConfig& config = {}) const;
    /// predict()'s index image and, drawn in the same pass (each pixel's tests computed once),
    /// the index image predict() would give with min_confidence = second_min_confidence: what
    /// fusion associates with, and what the model shows where the nearest surfel is not
    /// confident. About 1.3 renderings' cost for two. Errors as predict().
    Status predict_two_layers(const Eigen::Isometry3f& world_T_camera, const io::Intrinsics& k,
                              int width, int height, int frame_index,
                              const PredictionConfig& config, float second_min_confidence,
                              TwoLayerPrediction& out) const;
    /// The rendering of the map after fuse() (as predict() with min_confidence), made from a
    /// predict_two_layers() of the map before it at the same pose instead of rendering again:
    /// each pixel shows the nearest surfel if it is still there and now has min_confidence,
    /// else the nearest confident one (second layer; surfel indices brought up to date by
    /// FuseOptions::index_after), with its fused normal and colour and its vertex where the
    /// pixel's ray meets the fused surfel's plane (splat mode; its centre in points mode).
    /// It differs from a rendering only where fusion moved a surfel across another's depth or
    /// made a hidden surfel confident. kInvalidArgument for index images not of
    /// predict_two_layers or intrinsics as predict() rejects.
    Status refresh_prediction(const std::vector<int32_t>& index_after,
                              const TwoLayerPrediction& layers,
                              const Eigen::Isometry3f& world_T_camera, const io::Intrinsics& k,
                              float min_confidence, const PredictionConfig& config,
                              ModelPrediction& out) const;
    /// predict() into `out`, whose images are overwritten in place when they already have the
    /// right size and type (so a caller that keeps `out` allocates nothing per frame; copies of
    /// its cv::Mat headers see the new contents). On error `out` is unspecified.
    Status predict_into(const Eigen::Isometry3f& world_T_camera, const io::Intrinsics& k, int width,
                        int height, int frame_index, const PredictionConfig& config,
                        ModelPrediction& out) const;

    /// Replaces the surfels (a checkpoint's, in their storage order) and the count of
    /// observations rejected by capacity. kInvalidArgument when there are more than
    /// config.max_surfels or one has a non-finite position, normal or radius.
    Status restore(std::vector<Surfel> surfels, uint64_t total_rejected_by_capacity);

    size_t size() const { return surfels_.size(); }
    size_t stable_count() const;
    const std::vector<Surfel>& surfels() const { return surfels_; }
    const SurfelMapConfig& config() const { return config_; }
    bool is_stable(const Surfel& s) const { return s.confidence >= config_.stable_confidence; }
    /// True if the surfel was seen within the active time window before frame_index.
    bool is_active(const Surfel& s, int frame_index) const {
        return frame_index - s.last_seen_frame <= config_.active_time_window_frames;
    }
    /// Indices of the active surfels at frame_index.
    std::vector<size_t> active(int frame_index) const;

    /// True once an observation has been dropped because the map was full.
    bool capacity_reached() const { return total_rejected_by_capacity_ > 0; }
    /// Observations dropped for lack of capacity since construction.
    uint64_t total_rejected_by_capacity() const { return total_rejected_by_capacity_; }

    /// Writes the map (world frame) as a binary little-endian PLY: x y z, nx ny nz,
    /// red green blue (uchar), radius, confidence (float). Only stable surfels if stable_only.
    /// Errors of io::write_ply (kIoError naming the file).
    Status write_ply(const std::string& file, bool stable_only = true) const;

  private:
    /// clean(), composing its moves into index_after when not null (FuseOptions::index_after).
    size_t clean(int frame_index, std::vector<int32_t>* index_after);
    /// Keeps the surfels i for which keep(i) is true, in their order; returns how many went.
    /// index_after (may be null): each entry >= 0 is replaced by where that surfel went.
    template <class Keep>
    size_t compact(const Keep& keep, std::vector<int32_t>* index_after);
    /// The observation weight factors per column and row (weight_u_, weight_v_).
    void prepare_weights(int width, int height, const io::Intrinsics& intrinsics,
                         const cv::Size& sensor_size);
    /// Fills zbuffer_index_ with, per pixel, the nearest active surfel projecting there (-1 if
    /// none).
    void project_active(const Eigen::Isometry3f& camera_T_world, const io::Intrinsics& k, int width,
                        int height, int frame_index);
    /// Free-space pass of fuse(): weakens or removes the surfels [0, existing) that the frame
    /// saw through (see SurfelMapConfig::remove_free_space); updates stats.
    void remove_free_space(const cv::Mat& vertex_map_cam, const cv::Mat& mask,
                           const Eigen::Isometry3f& camera_T_world, const io::Intrinsics& k,
                           int frame_index, size_t existing, FusionStats& stats,
                           bool keep_stable = false, std::vector<int32_t>* index_after = nullptr);

    SurfelMapConfig config_;
    std::vector<Surfel> surfels_;
    uint64_t total_rejected_by_capacity_ = 0;
    // Reused across frames so that fuse() allocates only when the image size grows.
    std::vector<int32_t> zbuffer_index_;
    std::vector<float> zbuffer_depth_;
    std::vector<float> weight_u_;  ///< per column and per row factors of the observation weight
    std::vector<float> weight_v_;
    static constexpr int32_t kNoCandidate = -1;   ///< pixel_candidate_: nothing associated
    static constexpr int32_t kKnownSurface = -2;  ///< pixel_candidate_: see known_surface
    static constexpr int32_t kInvalidPixel = -3;  ///< pixel_candidate_: no observation (masked)
    /// Per pixel of the index image: the surfel shown there, in the camera (depth, projected
    /// centre) and its world normal, computed once per frame rather than once per window that
    /// looks at it. depth NaN: no surfel.
    struct Shown {
        float depth, u, v;
        Eigen::Vector3f normal;
    };
    std::vector<Shown> shown_;
    std::vector<int32_t> pixel_candidate_;  ///< per pixel: chosen surfel or a k* marker
    std::vector<float> pixel_distance_;     ///< its squared pixel distance to the centre
    std::vector<int32_t> owner_pixel_;   ///< per existing surfel: the pixel that updates it
    std::vector<float> owner_distance_;  ///< its squared distance to the projected centre
    std::vector<float> measured_depth_;  ///< metres, 0 = no evidence (free-space pass)
    std::vector<uint8_t> remove_flags_;  ///< per surfel, free-space pass
    std::vector<int32_t> moved_to_;      ///< per surfel, compact(): its new index or -1
};

}  // namespace df::map
