#include "slam/tracker.hpp"

#include <gtest/gtest.h>

#include <cstdio>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "slam/depth_maps.hpp"
#include "slam/frame.hpp"

namespace df::slam {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr uint8_t kBoxId = 10;

// --- A tiny analytic ray caster: textured planes bounding a room, and an axis-aligned box. ---

/// The half-space n . x <= d, seen from inside; its boundary carries a texture in the
/// coordinates (a_axis . x, b_axis . x).
struct Plane {
    Eigen::Vector3d n;
    double d;
    Eigen::Vector3d a_axis, b_axis;
    double phase;
};

struct Scene {
    std::vector<Plane> planes;
    bool has_box = false;
    Eigen::Vector3d box_min, box_max;
    double texture_scale = 1.0;  ///< multiplies the texture's wavelengths
};

/// Smooth texture in 0.1 .. 0.9 with wavelengths from 8 to 23 cm (times `scale`): gradients at
/// every level.
double texture(double a, double b, double phase, double scale) {
    a /= scale;
    b /= scale;
    return 0.5 + 0.22 * std::sin(2 * kPi * a / 0.23 + phase) * std::cos(2 * kPi * b / 0.19 - phase) +
           0.15 * std::sin(2 * kPi * (a + 0.6 * b) / 0.083 + 2 * phase);
}

cv::Vec3b colour_of(double t) {
    const auto byte = [](double v) {
        return static_cast<uint8_t>(std::lround(std::min(255.0, std::max(0.0, 255.0 * v))));
    };
    return cv::Vec3b(byte(t), byte(0.9 * t + 0.05), byte(1.0 - 0.7 * t));
}

/// The room bounded by a right wall (x = 1.2), the floor (y = 0.8, y is down) and a back wall
/// (z = 2.0), optionally with a box standing on the floor near the corner.
Scene room_corner(bool with_box, const Eigen::Vector3d& box_shift = Eigen::Vector3d::Zero()) {
    Scene s;
    s.planes.push_back({{1, 0, 0}, 1.2, {0, 0, 1}, {0, 1, 0}, 0.0});
    s.planes.push_back({{0, 1, 0}, 0.8, {1, 0, 0}, {0, 0, 1}, 1.1});
    s.planes.push_back({{0, 0, 1}, 2.0, {1, 0, 0}, {0, 1, 0}, 2.3});
    s.has_box = with_box;
    s.box_min = Eigen::Vector3d(0.45, 0.4, 1.2) + box_shift;
    s.box_max = Eigen::Vector3d(0.85, 0.8, 1.6) + box_shift;
    return s;
}

/// One textured plane 1.6 m in front of the origin, slightly tilted.
Scene textured_plane() {
    Scene s;
    const Eigen::Vector3d n = Eigen::Vector3d(0.15, -0.1, 1.0).normalized();
    const Eigen::Vector3d a = n.cross(Eigen::Vector3d::UnitY()).normalized();
    s.planes.push_back({n, 1.6, a, n.cross(a), 0.7});
    s.texture_scale = 2.0;
    return s;
}

/// Camera at `eye` looking at `target`, image y towards world +y (down).
Eigen::Isometry3d look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
    const Eigen::Vector3d z = (target - eye).normalized();
    const Eigen::Vector3d x = Eigen::Vector3d::UnitY().cross(z).normalized();
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear().col(0) = x;
    pose.linear().col(1) = z.cross(x);
    pose.linear().col(2) = z;
    pose.translation() = eye;
    return pose;
}

/// A motion in the camera frame: translation (metres) and rotation about `axis` (degrees).
Eigen::Isometry3d motion(const Eigen::Vector3d& t, const Eigen::Vector3d& axis, double deg) {
    Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
    m.linear() = Eigen::AngleAxisd(deg * kDeg, axis.normalized()).toRotationMatrix();
    m.translation() = t;
    return m;
}

struct Rendered {
    io::RgbdImage image;
    cv::Mat ids;  ///< CV_8UC1: 0 nothing, 1 + plane index, kBoxId box
    Frame frame;
    Eigen::Isometry3d world_T_camera;
};

/// Nearest hit of the ray eye + t dir (t > 0) with the box, or +inf; `axis` is the face's axis.
double hit_box(const Scene& s, const Eigen::Vector3d& eye, const Eigen::Vector3d& dir, int& axis) {
    double t_near = -std::numeric_limits<double>::infinity();
    double t_far = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 3; ++i) {
        if (std::abs(dir(i)) < 1e-12) {
            if (eye(i) < s.box_min(i) || eye(i) > s.box_max(i)) return t_far;
            continue;
        }
        double t0 = (s.box_min(i) - eye(i)) / dir(i), t1 = (s.box_max(i) - eye(i)) / dir(i);
        if (t0 > t1) std::swap(t0, t1);
        if (t0 > t_near) {
            t_near = t0;
            axis = i;
        }
        t_far = std::min(t_far, t1);
    }
    return (t_near <= t_far && t_near > 0.0) ? t_near : std::numeric_limits<double>::infinity();
}

Rendered render(const Scene& s, const Eigen::Isometry3d& world_T_camera, int width = 640,
                int height = 480) {
    Rendered out;
    out.world_T_camera = world_T_camera;
    io::RgbdImage& image = out.image;
    image.intrinsics = scale_intrinsics(io::Intrinsics{}, width == 640 ? 0 : 1);
    image.depth = cv::Mat(height, width, CV_16UC1, cv::Scalar(0));
    image.rgb = cv::Mat(height, width, CV_8UC3, cv::Scalar(0, 0, 0));
    out.ids = cv::Mat(height, width, CV_8UC1, cv::Scalar(0));
    const io::Intrinsics& k = image.intrinsics;
    const Eigen::Vector3d eye = world_T_camera.translation();
    for (int v = 0; v < height; ++v) {
        for (int u = 0; u < width; ++u) {
            // The ray has camera z = 1, so the hit parameter t is the depth.
            const Eigen::Vector3d dir =
                world_T_camera.linear() * Eigen::Vector3d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1);
            double best = std::numeric_limits<double>::infinity();
            uint8_t id = 0;
            for (size_t i = 0; i < s.planes.size(); ++i) {
                const double nd = s.planes[i].n.dot(dir);
                if (nd <= 1e-12) continue;
                const double t = (s.planes[i].d - s.planes[i].n.dot(eye)) / nd;
                if (t > 0.0 && t < best) {
                    best = t;
                    id = static_cast<uint8_t>(i + 1);
                }
            }
            int axis = 0;
            if (s.has_box) {
                const double t = hit_box(s, eye, dir, axis);
                if (t < best) {
                    best = t;
                    id = kBoxId;
                }
            }
            if (id == 0) continue;
            const Eigen::Vector3d p = eye + best * dir;
            double tex;
            if (id == kBoxId) {
                tex = texture(p((axis + 1) % 3), p((axis + 2) % 3), 0.4 + axis, s.texture_scale);
            } else {
                const Plane& plane = s.planes[id - 1u];
                tex = texture(plane.a_axis.dot(p), plane.b_axis.dot(p), plane.phase, s.texture_scale);
            }
            image.depth.at<uint16_t>(v, u) =
                static_cast<uint16_t>(std::lround(std::min(best, 13.0) * image.depth_units_per_m));
            image.rgb.at<cv::Vec3b>(v, u) = colour_of(tex);
            out.ids.at<uint8_t>(v, u) = id;
        }
    }
    Result<Frame> frame = preprocess(image, PreprocessConfig{});
    EXPECT_TRUE(frame.is_ok()) << frame.status().to_string();
    if (frame.is_ok()) out.frame = std::move(frame).value();
    return out;
}

/// The model as a map would predict it at A's pose: A's own vertices, normals and colours.
ModelView model_of(const Rendered& a) {
    return ModelView{a.frame.levels[0].vertex, a.frame.levels[0].normal, a.image.rgb};
}

double translation_error_m(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
    return (a.translation() - b.translation()).norm();
}

double rotation_error_deg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
    return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() / kDeg;
}

/// Tracks B against A's model starting from A's pose.
TrackingResult track_ok(const Rendered& a, const Rendered& b, const TrackingConfig& config = {},
                        const cv::Mat& mask = cv::Mat()) {
    Result<TrackingResult> r =
        track(b.frame, model_of(a), a.world_T_camera, a.world_T_camera, mask, config);
    EXPECT_TRUE(r.is_ok()) << r.status().to_string();
    return r.is_ok() ? r.value() : TrackingResult{};
}

const Eigen::Isometry3d kCornerA = look_at({0.0, 0.0, 0.0}, {1.2, 0.8, 2.0});
const Eigen::Isometry3d kCornerMotion =
    motion({0.03, -0.02, 0.025}, {0.3, 1.0, 0.2}, 2.5);

void expect_pose_near(const TrackingResult& r, const Eigen::Isometry3d& truth) {
    EXPECT_EQ(r.state, TrackingState::kOk) << r.reason;
    EXPECT_LT(translation_error_m(r.world_T_camera, truth), 0.002);
    EXPECT_LT(rotation_error_deg(r.world_T_camera, truth), 0.1);
}

TEST(Tracker, CornerWithBoxCombinedRecoversMotion) {
    const Scene scene = room_corner(true);
    const Rendered a = render(scene, kCornerA);
    const Rendered b = render(scene, kCornerA * kCornerMotion);
    const TrackingResult r = track_ok(a, b);
    expect_pose_near(r, b.world_T_camera);
    EXPECT_GT(r.inlier_ratio, 0.8f);
    EXPECT_LT(r.icp_rmse_m, 0.002f);
    EXPECT_GT(r.rgb_pixels, 10000);
    EXPECT_GT(r.condition, 1e-6);
    EXPECT_TRUE(r.reason.empty());
}

TEST(Tracker, CornerIcpOnlyRecoversMotion) {
    const Scene scene = room_corner(true);
    const Rendered a = render(scene, kCornerA);
    const Rendered b = render(scene, kCornerA * kCornerMotion);
    TrackingConfig config;
    config.use_rgb = false;
    const TrackingResult r = track_ok(a, b, config);
    expect_pose_near(r, b.world_T_camera);
    EXPECT_EQ(r.rgb_pixels, 0);
}

TEST(Tracker, ReturnsARigidPoseEvenFromSlightlyScaledInputs) {
    // Poses that went through many products lose orthonormality; the tracker must not pass the
    // error on (Isometry3d::inverse() transposes, which turns a scale 1+e into 1+3e per frame).
    const Scene scene = room_corner(true);
    const Rendered a = render(scene, kCornerA);
    const Rendered b = render(scene, kCornerA * kCornerMotion);
    Eigen::Isometry3d scaled = a.world_T_camera;
    scaled.linear() *= 1.0 + 1e-4;
    Result<TrackingResult> r = track(b.frame, model_of(a), scaled, scaled, cv::Mat(), {});
    ASSERT_TRUE(r.is_ok()) << r.status().to_string();
    expect_pose_near(*r, b.world_T_camera);
    const Eigen::Matrix3d rot = r->world_T_camera.linear();
    EXPECT_LT((rot.transpose() * rot - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    EXPECT_NEAR(rot.determinant(), 1.0, 1e-12);
}

TEST(Tracker, HalfResolutionInputRecoversMotion) {
    const Scene scene = room_corner(true);
    const Rendered a = render(scene, kCornerA, 320, 240);
    const Rendered b = render(scene, kCornerA * kCornerMotion, 320, 240);
    TrackingConfig config;
    config.min_inliers = 200;
    expect_pose_near(track_ok(a, b, config), b.world_T_camera);
}

TEST(Tracker, CoarsePixelStepStillRecoversMotion) {
    const Scene scene = room_corner(true);
    const Rendered a = render(scene, kCornerA);
    const Rendered b = render(scene, kCornerA * kCornerMotion);
    TrackingConfig config;
    config.pixel_step = {2, 1, 1};
    expect_pose_near(track_ok(a, b, config), b.world_T_camera);
}

TEST(Tracker, PhotometricTermRecoversSlidingAlongTexturedPlane) {
    const Scene scene = textured_plane();
    const Eigen::Isometry3d pose_a = Eigen::Isometry3d::Identity();
    // Slide 4 cm within the plane and turn 1.5 deg about its normal: invisible to ICP.
    const Plane& plane = scene.planes[0];
    Eigen::Isometry3d slide = Eigen::Isometry3d::Identity();
    slide.translation() = 0.03 * plane.a_axis + 0.025 * plane.b_axis;
    slide.linear() = Eigen::AngleAxisd(1.5 * kDeg, plane.n).toRotationMatrix();
    const Rendered a = render(scene, pose_a);
    const Rendered b = render(scene, slide * pose_a);

    TrackingConfig icp_only;
    icp_only.use_rgb = false;
    const TrackingResult geometric = track_ok(a, b, icp_only);
    EXPECT_TRUE(geometric.state == TrackingState::kLost ||
                translation_error_m(geometric.world_T_camera, b.world_T_camera) > 0.01)
        << "ICP alone cannot see a slide along a plane";
    if (geometric.state == TrackingState::kLost) {
        EXPECT_NE(geometric.reason.find("condition"), std::string::npos) << geometric.reason;
    }

    const TrackingResult combined = track_ok(a, b);
    expect_pose_near(combined, b.world_T_camera);
}

TEST(Tracker, MaskedMovingBoxIsIgnored) {
    const Rendered a = render(room_corner(true), kCornerA);
    // The box moved 5 cm between the frames; the model still has it where it was.
    const Rendered b =
        render(room_corner(true, {-0.05, 0.0, 0.04}), kCornerA * kCornerMotion);
    const cv::Mat mask = b.ids == kBoxId;
    ASSERT_GT(cv::countNonZero(mask), 5000);

    const TrackingResult masked = track_ok(a, b, TrackingConfig{}, mask);
    expect_pose_near(masked, b.world_T_camera);
    TrackingConfig icp_only;
    icp_only.use_rgb = false;
    expect_pose_near(track_ok(a, b, icp_only, mask), b.world_T_camera);

    // Without the mask the moved box pulls ICP out of tolerance (about 5 mm, 0.2 deg) ...
    const TrackingResult unmasked = track_ok(a, b, icp_only);
    const double icp_error_m = translation_error_m(unmasked.world_T_camera, b.world_T_camera);
    EXPECT_TRUE(icp_error_m > 0.002 ||
                rotation_error_deg(unmasked.world_T_camera, b.world_T_camera) > 0.1);
    // ... and less so both terms, the photometric one as ICP's equal at the finest level.
    const TrackingResult combined = track_ok(a, b);
    EXPECT_LT(translation_error_m(combined.world_T_camera, b.world_T_camera), icp_error_m);
    std::printf("moved box, unmasked: ICP alone %.2f mm off, ICP + photometric %.2f mm off\n",
                icp_error_m * 1e3,
                translation_error_m(combined.world_T_camera, b.world_T_camera) * 1e3);
}

TEST(Tracker, EachUpdateStaysInItsTrustRegionAndTrackingStillConverges) {
    // A near-singular system (a small object at a coarse level) can ask for a step of metres;
    // each update is scaled into max_step_translation_m / max_step_rotation_rad.
    const Scene scene = room_corner(true);
    const Rendered a = render(scene, kCornerA);
    const Rendered b = render(scene, kCornerA * kCornerMotion);  // 4.4 cm, 2.5 deg away
    TrackingConfig config;
    config.max_step_translation_m = 0.01f;
    config.max_step_rotation_rad = 0.01f;
    config.iterations = {1, 0, 0};
    const TrackingResult one = track_ok(a, b, config);
    const Eigen::Isometry3d moved = a.world_T_camera.inverse() * one.estimate;
    EXPECT_LE(moved.translation().norm(), 0.01 + 1e-6);
    EXPECT_LE(Eigen::AngleAxisd(moved.linear()).angle(), 0.01 + 1e-6);
    EXPECT_GT(moved.translation().norm(), 0.009) << "the step was not towards the motion";
    // Smaller steps, more of them: the same pose as unbounded tracking.
    config.iterations = {10, 10, 20};
    expect_pose_near(track_ok(a, b, config), b.world_T_camera);
}

TEST(Tracker, HugeJumpIsLost) {
    const Scene scene = room_corner(true);
    const Rendered a = render(scene, kCornerA);
    // One metre away, looking at another part of the room.
    const Rendered b = render(scene, look_at({-0.6, -0.3, 0.7}, {-0.6, 0.8, 2.0}));
    const TrackingResult r = track_ok(a, b);
    EXPECT_EQ(r.state, TrackingState::kLost);
    EXPECT_FALSE(r.reason.empty());
    EXPECT_TRUE(r.world_T_camera.isApprox(a.world_T_camera)) << "kLost returns the initial guess";
}

TEST(Tracker, EmptyModelIsLost) {
    const Rendered b = render(room_corner(true), kCornerA);
    const cv::Mat zeros3(480, 640, CV_32FC3, cv::Scalar::all(0));
    const ModelView empty{zeros3, zeros3, cv::Mat(480, 640, CV_8UC3, cv::Scalar::all(0))};
    Result<TrackingResult> r =
        track(b.frame, empty, kCornerA, kCornerA, cv::Mat(), TrackingConfig{});
    ASSERT_TRUE(r.is_ok()) << r.status().to_string();
    EXPECT_EQ(r->state, TrackingState::kLost);
    EXPECT_EQ(r->inliers, 0);
    EXPECT_NE(r->reason.find("min_inliers"), std::string::npos) << r->reason;
}

void expect_invalid(const Result<TrackingResult>& r, const std::string& names) {
    ASSERT_FALSE(r.is_ok());
    EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument);
    EXPECT_NE(r.status().message().find(names), std::string::npos) << r.status().message();
}

TEST(Tracker, BadInputsAreInvalidArguments) {
    const Rendered a = render(room_corner(false), kCornerA);
    const ModelView good = model_of(a);
    const Eigen::Isometry3d pose = kCornerA;
    const auto run = [&](const ModelView& m, const cv::Mat& mask, const TrackingConfig& c) {
        return track(a.frame, m, pose, pose, mask, c);
    };
    ModelView small = good;
    small.vertex = cv::Mat(240, 320, CV_32FC3, cv::Scalar::all(0));
    expect_invalid(run(small, cv::Mat(), {}), "vertex");
    ModelView wrong_type = good;
    wrong_type.normal = cv::Mat(480, 640, CV_64FC3, cv::Scalar::all(0));
    expect_invalid(run(wrong_type, cv::Mat(), {}), "normal");
    ModelView no_colour = good;
    no_colour.colour = cv::Mat();
    expect_invalid(run(no_colour, cv::Mat(), {}), "colour");
    TrackingConfig icp_only;
    icp_only.use_rgb = false;
    EXPECT_TRUE(run(no_colour, cv::Mat(), icp_only).is_ok()) << "colour unused without rgb";
    expect_invalid(run(good, cv::Mat(100, 100, CV_8UC1), {}), "mask");

    TrackingConfig c;
    c.iterations = {};
    expect_invalid(run(good, cv::Mat(), c), "iterations");
    c = {};
    c.iterations = {10, 5, 4, 2};  // the frame has 3 levels
    c.pixel_step = {1, 1, 1, 1};
    c.rgb_min_gradient = {5, 3, 1, 1};
    expect_invalid(run(good, cv::Mat(), c), "levels");
    c = {};
    c.iterations = {10, -1, 4};
    expect_invalid(run(good, cv::Mat(), c), "iterations[1]");
    c = {};
    c.pixel_step = {1, 1};
    expect_invalid(run(good, cv::Mat(), c), "pixel_step");
    c = {};
    c.rgb_min_gradient = {5, 3};
    expect_invalid(run(good, cv::Mat(), c), "rgb_min_gradient");
    c = {};
    c.icp_max_distance_m = -0.1f;
    expect_invalid(run(good, cv::Mat(), c), "icp_max_distance_m");
    c = {};
    c.rgb_huber = 0.f;
    expect_invalid(run(good, cv::Mat(), c), "rgb_huber");
    EXPECT_EQ(validate(TrackingConfig{}), "");
}

TEST(Tracker, DeterministicWhateverTheThreadCount) {
    const Scene scene = room_corner(true);
    const Rendered a = render(scene, kCornerA);
    const Rendered b = render(scene, kCornerA * kCornerMotion);
    const int threads = cv::getNumThreads();
    cv::setNumThreads(4);
    const TrackingResult first = track_ok(a, b);
    const TrackingResult second = track_ok(a, b);
    cv::setNumThreads(1);
    const TrackingResult single = track_ok(a, b);
    cv::setNumThreads(threads);
    for (const TrackingResult* r : {&second, &single}) {
        EXPECT_EQ(std::memcmp(first.world_T_camera.matrix().data(),
                              r->world_T_camera.matrix().data(), sizeof(double) * 16),
                  0);
        EXPECT_EQ(first.inliers, r->inliers);
        EXPECT_EQ(first.rgb_pixels, r->rgb_pixels);
        EXPECT_EQ(first.condition, r->condition);
        EXPECT_EQ(first.iterations, r->iterations);
    }
}

TEST(Tracker, StateNames) {
    EXPECT_STREQ(to_string(TrackingState::kOk), "ok");
    EXPECT_STREQ(to_string(TrackingState::kLost), "lost");
}

}  // namespace
}  // namespace df::slam
