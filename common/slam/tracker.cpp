#include "slam/tracker.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <sstream>

#include "slam/pose.hpp"
#include "slam/tracker_terms.hpp"

namespace df::slam {

namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;
using tracker_detail::NormalEquations;

// Fewer contributing pixels than unknowns cannot determine a step.
constexpr int kMinRowsForStep = 6;

std::string describe_mat(const cv::Mat& m) {
    std::ostringstream out;
    if (m.empty()) {
        out << "empty";
    } else {
        out << cv::typeToString(m.type()) << " " << m.cols << "x" << m.rows;
    }
    return out.str();
}

std::string validate_inputs(const Frame& frame, const ModelView& model, const cv::Mat& mask,
                            const TrackingConfig& config) {
    std::ostringstream msg;
    const size_t levels = config.iterations.size();
    if (frame.levels.size() < levels) {
        msg << "frame has " << frame.levels.size() << " pyramid levels, TrackingConfig::iterations"
            << " has " << levels << " entries";
        return msg.str();
    }
    const cv::Size size(frame.levels[0].width(), frame.levels[0].height());
    const std::string expected = " of the frame's level-0 size " + std::to_string(size.width) +
                                 "x" + std::to_string(size.height);
    for (size_t l = 0; l < levels; ++l) {
        const FrameLevel& level = frame.levels[l];
        if (level.smoothed_vertex.type() != CV_32FC3 || level.normal.type() != CV_32FC3 ||
            level.intensity.type() != CV_32F || level.grad_x.type() != CV_32F ||
            level.grad_y.type() != CV_32F || level.depth_m.type() != CV_32F ||
            level.smoothed_vertex.size() != level.depth_m.size() ||
            level.normal.size() != level.depth_m.size() ||
            level.intensity.size() != level.depth_m.size() ||
            level.grad_x.size() != level.depth_m.size() ||
            level.grad_y.size() != level.depth_m.size() ||
            level.depth_m.cols != size.width >> l || level.depth_m.rows != size.height >> l) {
            msg << "frame level " << l << " is not a preprocess() level (depth_m "
                << describe_mat(level.depth_m) << ", smoothed_vertex " << describe_mat(level.smoothed_vertex) << ")";
            return msg.str();
        }
    }
    if (model.vertex.type() != CV_32FC3 || model.vertex.size() != size) {
        msg << "ModelView::vertex must be CV_32FC3" << expected << ", got "
            << describe_mat(model.vertex);
    } else if (model.normal.type() != CV_32FC3 || model.normal.size() != size) {
        msg << "ModelView::normal must be CV_32FC3" << expected << ", got "
            << describe_mat(model.normal);
    } else if (config.use_rgb && (model.colour.type() != CV_8UC3 || model.colour.size() != size)) {
        msg << "ModelView::colour must be CV_8UC3" << expected
            << " when TrackingConfig::use_rgb is true, got " << describe_mat(model.colour);
    } else if (!mask.empty() && (mask.type() != CV_8UC1 || mask.size() != size)) {
        msg << "mask must be empty or CV_8UC1" << expected << ", got " << describe_mat(mask);
    }
    return msg.str();
}

tracker_detail::PoseF to_float(const Eigen::Isometry3d& pose) {
    tracker_detail::PoseF out{};
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) out.r[r * 3 + c] = static_cast<float>(pose.linear()(r, c));
        out.t[r] = static_cast<float>(pose.translation()(r));
    }
    return out;
}

// A += scale_a * eq.a (both triangles), b += scale_b * eq.b.
void add_scaled(const NormalEquations& eq, double scale_a, double scale_b, Matrix6d& a,
                Vector6d& b) {
    int k = 0;
    for (int i = 0; i < 6; ++i) {
        for (int j = i; j < 6; ++j) {
            const double v = scale_a * eq.a[static_cast<size_t>(k++)];
            a(i, j) += v;
            if (j != i) a(j, i) += v;
        }
        b(i) += scale_b * eq.b[static_cast<size_t>(i)];
    }
}

// Exp of the increment: rotation exp(w), translation t (first-order equal to the SE(3) exp,
// which is all Gauss-Newton needs).
Eigen::Isometry3d increment(const Vector6d& xi) {
    Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
    const Eigen::Vector3d w = xi.tail<3>();
    const double angle = w.norm();
    if (angle > 0.0) out.linear() = Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
    out.translation() = xi.head<3>();
    return out;
}

// The factor (<= 1) that brings a Gauss-Newton update within the configured trust region.
double step_scale(const Vector6d& xi, const TrackingConfig& c) {
    double scale = 1.0;
    const double t = xi.head<3>().norm(), r = xi.tail<3>().norm();
    if (c.max_step_translation_m > 0.f && t > c.max_step_translation_m)
        scale = std::min(scale, c.max_step_translation_m / t);
    if (c.max_step_rotation_rad > 0.f && r > c.max_step_rotation_rad)
        scale = std::min(scale, c.max_step_rotation_rad / r);
    return scale;
}

double condition_of(const Matrix6d& a) {
    const Eigen::SelfAdjointEigenSolver<Matrix6d> solver(a, Eigen::EigenvaluesOnly);
    const auto& ev = solver.eigenvalues();  // ascending
    return ev(5) > 0.0 ? std::max(0.0, ev(0)) / ev(5) : 0.0;
}

// Figures of the finest level's last linearisation.
struct Figures {
    int valid = 0;
    int frame_valid = 0;  ///< valid, unmasked frame pixels at the finest level (pixel step)
    NormalEquations icp, rgb;
    double condition = 0.0;
};

/// The correspondences the inlier ratio counts (tracking.inlier_residual_m; 0: the ICP inliers).
int agreeing_count(const Figures& f, const TrackingConfig& c) {
    return c.inlier_residual_m > 0.f ? f.icp.agreeing : f.icp.used;
}

std::string lost_reason(const Figures& f, const TrackingResult& r, const Eigen::Isometry3d& moved,
                        const TrackingConfig& c) {
    std::ostringstream msg;
    const double moved_m = moved.translation().norm();
    const double moved_rad = Eigen::AngleAxisd(moved.linear()).angle();
    if (r.inliers < c.min_inliers) {
        msg << "ICP inliers " << r.inliers << " < min_inliers " << c.min_inliers << " ("
            << f.valid << " frame pixels on the model)";
    } else if (r.inlier_ratio < c.min_inlier_ratio) {
        msg << "ICP inlier ratio " << r.inlier_ratio << " (" << agreeing_count(f, c) << "/"
            << f.valid << " correspondences agree) < min_inlier_ratio " << c.min_inlier_ratio;
    } else if (f.frame_valid > 0 &&
               static_cast<float>(r.inliers) / static_cast<float>(f.frame_valid) <
                   c.min_frame_inlier_ratio) {
        msg << "ICP inliers " << r.inliers << " are less than min_frame_inlier_ratio "
            << c.min_frame_inlier_ratio << " of the " << f.frame_valid << " valid frame pixels";
    } else if (r.icp_rmse_m > c.max_icp_rmse_m) {
        msg << "ICP RMSE " << r.icp_rmse_m << " m > max_icp_rmse_m " << c.max_icp_rmse_m;
    } else if (r.condition < c.min_condition) {
        msg << "condition " << r.condition << " < min_condition " << c.min_condition
            << " (degenerate geometry/texture)";
    } else if (moved_m > c.max_translation_m) {
        msg << "moved " << moved_m << " m from the initial guess > max_translation_m "
            << c.max_translation_m;
    } else if (moved_rad > c.max_rotation_rad) {
        msg << "rotated " << moved_rad << " rad from the initial guess > max_rotation_rad "
            << c.max_rotation_rad;
    }
    return msg.str();
}

}  // namespace

const char* to_string(TrackingState state) {
    switch (state) {
        case TrackingState::kOk:
            return "ok";
        case TrackingState::kLost:
            return "lost";
    }
    return "unknown";
}

std::string validate(const TrackingConfig& c) {
    std::ostringstream msg;
    const size_t levels = c.iterations.size();
    if (levels == 0) {
        msg << "iterations must have one entry per pyramid level, got none";
    } else if (c.pixel_step.size() != levels) {
        msg << "pixel_step must have " << levels << " entries (one per iterations entry), got "
            << c.pixel_step.size();
    } else if (c.rgb_min_gradient.size() != levels) {
        msg << "rgb_min_gradient must have " << levels
            << " entries (one per iterations entry), got " << c.rgb_min_gradient.size();
    }
    if (!msg.str().empty()) return msg.str();
    return params::check(c);  // each value against its range in slam.proto
}

Result<TrackingResult> track(const Frame& frame, const ModelView& model,
                             const Eigen::Isometry3d& world_T_reference,
                             const Eigen::Isometry3d& initial_world_T_camera, const cv::Mat& mask,
                             const TrackingConfig& config) {
    if (std::string bad = validate(config); !bad.empty()) {
        return error(StatusCode::kInvalidArgument, "TrackingConfig: " + bad);
    }
    if (std::string bad = validate_inputs(frame, model, mask, config); !bad.empty()) {
        return error(StatusCode::kInvalidArgument,
                     "track frame " + std::to_string(frame.index) + ": " + bad);
    }
    const int levels = static_cast<int>(config.iterations.size());
    int finest = 0;  // the finest level with iterations; level 0 when none has any
    while (finest < levels && config.iterations[static_cast<size_t>(finest)] == 0) ++finest;
    if (finest == levels) finest = 0;

    const std::vector<tracker_detail::ModelLevel> model_levels =
        tracker_detail::build_model_pyramid(model, levels, config.use_rgb);
    const std::vector<cv::Mat> masks = tracker_detail::build_mask_pyramid(mask, levels);

    // Inputs projected onto SE(3) first: inverse() below is only exact for rigid poses.
    const Eigen::Isometry3d reference = orthonormalized(world_T_reference);
    const Eigen::Isometry3d initial = orthonormalized(initial_world_T_camera);
    Eigen::Isometry3d reference_T_camera = reference.inverse() * initial;
    TrackingResult result;
    Figures figures;
    for (int l = levels - 1; l >= 0; --l) {
        const size_t li = static_cast<size_t>(l);
        const int iterations = config.iterations[li];
        if (iterations == 0 && l != finest) continue;
        const FrameLevel& level = frame.levels[li];
        const int step = config.pixel_step[li];
        // ICP's wide basin first (coarse levels), both terms as equals at the finest.
        const double w = l == finest ? config.icp_weight : config.icp_weight_coarse;
        // With no iterations anywhere, the finest level is evaluated once, not updated.
        for (int it = 0; it < std::max(iterations, 1); ++it) {
            const tracker_detail::PoseF pose = to_float(reference_T_camera);
            int valid = 0;
            NormalEquations icp = tracker_detail::accumulate_icp(
                level, masks[li], step, model_levels[li], pose, config, valid);
            NormalEquations rgb;
            Matrix6d a = Matrix6d::Zero();
            Vector6d b = Vector6d::Zero();
            if (config.use_rgb) {
                rgb = tracker_detail::accumulate_rgb(model_levels[li], step, level, masks[li],
                                                     to_float(reference_T_camera.inverse()), pose,
                                                     config.rgb_min_gradient[li], config);
                // Residuals in units of their Huber thresholds make the terms commensurable;
                // then E = E_rgb + w^2 E_icp, whose Gauss-Newton step needs w^2 on both A and b
                // (w on b alone would shrink the step by 1/w where ICP dominates).
                double rgb_var = double(config.rgb_huber) * config.rgb_huber;
                double icp_var = double(config.icp_huber_m) * config.icp_huber_m;
                if (config.adaptive_weights && rgb.used > 0 && icp.used > 0) {
                    // Each term in units of its own robust residual spread (this iteration's
                    // Huber-weighted mean square), floored at a tenth of its threshold.
                    rgb_var = std::max(rgb.weighted_sq / rgb.used, rgb_var * 0.01);
                    icp_var = std::max(icp.weighted_sq / icp.used, icp_var * 0.01);
                }
                const double rgb_scale = 1.0 / rgb_var;
                const double icp_scale = w * w / icp_var;
                add_scaled(rgb, rgb_scale, rgb_scale, a, b);
                add_scaled(icp, icp_scale, icp_scale, a, b);
            } else {
                add_scaled(icp, 1.0, 1.0, a, b);
            }
            if (l == finest) {
                if (figures.frame_valid == 0) {
                    for (int y = 0; y < level.height(); y += step) {
                        const float* d = level.depth_m.ptr<float>(y);
                        const uint8_t* m = masks[li].empty() ? nullptr : masks[li].ptr<uint8_t>(y);
                        for (int x = 0; x < level.width(); x += step)
                            figures.frame_valid += (d[x] > 0.f) && !(m && m[x]) &&
                                                   (config.max_depth_m <= 0.f ||
                                                    d[x] <= config.max_depth_m);
                    }
                }
                figures.valid = valid;
                figures.icp = icp;
                figures.rgb = rgb;
                figures.condition = condition_of(a);
            }
            if (iterations == 0 || icp.used + rgb.used < kMinRowsForStep) break;
            if (it == 0 && icp.used < config.min_level_correspondences) break;
            Vector6d xi = a.ldlt().solve(-b);
            if (!xi.allFinite()) break;
            xi *= step_scale(xi, config);
            reference_T_camera = orthonormalized(increment(xi) * reference_T_camera);
            ++result.iterations;
            if (xi.head<3>().norm() < config.min_update_translation_m &&
                xi.tail<3>().norm() < config.min_update_rotation_rad) {
                break;
            }
        }
    }

    result.inliers = figures.icp.used;
    result.inlier_ratio = figures.valid > 0
                              ? static_cast<float>(agreeing_count(figures, config)) /
                                    static_cast<float>(figures.valid)
                              : 0.f;
    result.icp_rmse_m =
        figures.icp.used > 0
            ? static_cast<float>(std::sqrt(figures.icp.residual_sq / figures.icp.used))
            : 0.f;
    result.rgb_pixels = figures.rgb.used;
    result.rgb_rmse =
        figures.rgb.used > 0
            ? static_cast<float>(std::sqrt(figures.rgb.residual_sq / figures.rgb.used))
            : 0.f;
    result.condition = figures.condition;

    const Eigen::Isometry3d estimate = orthonormalized(reference * reference_T_camera);
    result.estimate = estimate;
    result.reason = lost_reason(figures, result, initial.inverse() * estimate, config);
    if (result.reason.empty()) {
        result.state = TrackingState::kOk;
        result.world_T_camera = estimate;
    } else {
        result.state = TrackingState::kLost;
        result.world_T_camera = initial;
    }
    return result;
}

Result<cv::Mat> residual_image(const Frame& frame, const ModelView& model,
                               const Eigen::Isometry3d& world_T_reference,
                               const Eigen::Isometry3d& world_T_camera,
                               const TrackingConfig& config, cv::Mat* photometric) {
    TrackingConfig no_rgb = config;
    no_rgb.use_rgb = false;  // the colour image is not needed here
    if (std::string bad = validate_inputs(frame, model, cv::Mat(), no_rgb); !bad.empty()) {
        return error(StatusCode::kInvalidArgument,
                     "residuals of frame " + std::to_string(frame.index) + ": " + bad);
    }
    const FrameLevel& level = frame.levels[0];
    const tracker_detail::PoseF pose =
        to_float(orthonormalized(world_T_reference).inverse() * orthonormalized(world_T_camera));
    const float* R = pose.r;
    const float* t = pose.t;
    const io::Intrinsics& k = level.intrinsics;
    const float fx = static_cast<float>(k.fx), fy = static_cast<float>(k.fy);
    const float cx = static_cast<float>(k.cx), cy = static_cast<float>(k.cy);
    const float max_z = config.max_depth_m > 0.f ? config.max_depth_m
                                                 : std::numeric_limits<float>::infinity();
    const float max_sin2 = config.icp_max_normal_sin * config.icp_max_normal_sin;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    cv::Mat out(level.height(), level.width(), CV_32F, cv::Scalar(nan));
    const bool with_photo = photometric != nullptr && model.colour.type() == CV_8UC3 &&
                            model.colour.size() == model.vertex.size();
    if (photometric != nullptr) {
        photometric->create(level.height(), level.width(), CV_32F);
        photometric->setTo(cv::Scalar(nan));
    }
    cv::parallel_for_(cv::Range(0, level.height()), [&](const cv::Range& range) {
        for (int y = range.start; y < range.end; ++y) {
            const cv::Vec3f* fv = level.vertex.ptr<cv::Vec3f>(y);
            const cv::Vec3f* fn = level.normal.ptr<cv::Vec3f>(y);
            float* o = out.ptr<float>(y);
            for (int x = 0; x < level.width(); ++x) {
                const cv::Vec3f& p = fv[x];
                if (!(p[2] > 0.f) || !(p[2] <= max_z) || !is_valid_normal(fn[x])) continue;
                const float qx = R[0] * p[0] + R[1] * p[1] + R[2] * p[2] + t[0];
                const float qy = R[3] * p[0] + R[4] * p[1] + R[5] * p[2] + t[1];
                const float qz = R[6] * p[0] + R[7] * p[1] + R[8] * p[2] + t[2];
                if (!(qz > 0.f)) continue;
                const int u = cvRound(fx * qx / qz + cx);
                const int v = cvRound(fy * qy / qz + cy);
                if (u < 0 || v < 0 || u >= model.vertex.cols || v >= model.vertex.rows) continue;
                const cv::Vec3f& m = model.vertex.at<cv::Vec3f>(v, u);
                const cv::Vec3f& mn = model.normal.at<cv::Vec3f>(v, u);
                if (!(m[2] > 0.f) || !is_valid_normal(mn)) continue;
                const cv::Vec3f& n = fn[x];
                const float nx = R[0] * n[0] + R[1] * n[1] + R[2] * n[2];
                const float ny = R[3] * n[0] + R[4] * n[1] + R[5] * n[2];
                const float nz = R[6] * n[0] + R[7] * n[1] + R[8] * n[2];
                const float dx = qx - m[0], dy = qy - m[1], dz = qz - m[2];
                const float sx = ny * mn[2] - nz * mn[1], sy = nz * mn[0] - nx * mn[2],
                            sz = nx * mn[1] - ny * mn[0];
                const bool agree = nx * mn[0] + ny * mn[1] + nz * mn[2] > 0.f &&
                                   sx * sx + sy * sy + sz * sz <= max_sin2;
                const float r = agree ? std::fabs(mn[0] * dx + mn[1] * dy + mn[2] * dz)
                                      : std::sqrt(dx * dx + dy * dy + dz * dz);
                const float q2 = qx * qx + qy * qy + qz * qz, m2 = m.dot(m);
                o[x] = q2 >= m2 ? r : -r;
                if (with_photo) {
                    const cv::Vec3b& c = model.colour.at<cv::Vec3b>(v, u);
                    if (c[0] != 0 || c[1] != 0 || c[2] != 0) {
                        const float model_i = 0.299f * c[0] + 0.587f * c[1] + 0.114f * c[2];
                        photometric->at<float>(y, x) =
                            std::fabs(level.intensity.at<float>(y, x) - model_i);
                    }
                }
            }
        }
    });
    return out;
}

}  // namespace df::slam
