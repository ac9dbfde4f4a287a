#pragma once
/// A Kinect-v1-like sensor model applied to a noise-free render. Every effect can be switched
/// off; all randomness is a function of (seed, frame, pixel), so output is deterministic.
///
/// Depth, in this order: projector shadows, holes at depth edges, at grazing angles and on dark
/// materials, random speckle holes; axial Gaussian noise sigma(z) = a + b (z - z0)^2; disparity
/// quantisation (steps of 1/8 px for a 7.5 cm baseline); range limits; 16-bit units.
/// Colour: auto-exposure drift, vignetting, a slight optical blur, signal-dependent noise.
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "io/rgbd_image.hpp"
#include "sim/render.hpp"

namespace df::sim {

struct SensorConfig {
    bool depth_noise = true;
    double sigma_a_m = 0.0012, sigma_b_per_m = 0.0019, sigma_z0_m = 0.4;
    bool quantisation = true;
    double baseline_m = 0.075;         ///< IR camera to projector, along camera +x
    double disparity_step_px = 0.125;  ///< Kinect v1: 1/8 pixel of its own 640-wide images
    int native_width_px = 640;         ///< the sensor's resolution: steps stay the same in metres
                                       ///< whatever size is rendered
    bool projector_shadow = true;      ///< background just left of a near object is unlit
    double shadow_margin_px = 1.0;     ///< disparity by which an occluder must be nearer
    bool edge_holes = true;
    double edge_jump = 0.04;  ///< relative depth jump between neighbours that is an edge
    double edge_hole_probability = 0.55;
    bool grazing_holes = true;
    double grazing_start_deg = 78, grazing_full_deg = 88;
    bool dropouts = true;  ///< material depth_dropout and random speckle holes
    double speckle_probability = 0.002;
    double min_range_m = 0.4, max_range_m = 8.0;

    bool colour_noise = true;
    double colour_sigma = 1.5;  ///< 8-bit levels, plus shot noise 0.02 per level
    bool exposure_changes = true;
    double exposure_amplitude = 0.15;  ///< relative gain drift
    bool vignetting = true;
    double vignetting_strength = 0.22;  ///< relative darkening in the corners
    bool colour_blur = true;
    double blur_sigma_px = 0.6;
    /// Motion blur of the colour image: the colour is the mean of blur_samples renders spread
    /// over the exposure time, centred on the frame's stamp (depth and instances stay those of
    /// the centre). Off by default (a still or slow camera shows none); on in static_fast.
    bool motion_blur = false;
    double exposure_s = 0.02;
    int blur_samples = 5;
    double gain = 1.0;  ///< overall exposure

    /// An ideal sensor: exact depth and colour (only the range limits remain).
    static SensorConfig ideal();
};

/// Names of the switchable effects: depth_noise, quantisation, projector_shadow, edge_holes,
/// grazing_holes, dropouts, colour_noise, exposure_changes, vignetting, colour_blur,
/// motion_blur.
const std::vector<std::string>& sensor_effects();
/// Switches effect `name` on or off; false for an unknown name.
bool set_sensor_effect(SensorConfig* config, const std::string& name, bool enabled);

/// Axial depth noise standard deviation at depth z (metres), without quantisation.
double depth_sigma(const SensorConfig& config, double z_m);
/// Focal length (px) of the sensor at its native width, for images `width` pixels wide with
/// focal length fx.
double native_fx(const SensorConfig& config, double fx, int width);
/// Depth step of the disparity quantisation at depth z (metres), 0 if off. fx_native: native_fx().
double quantisation_step(const SensorConfig& config, double fx_native, double z_m);
/// Exposure gain at time t_s (1 without exposure changes).
double exposure_gain(const SensorConfig& config, uint64_t seed, double t_s);

struct SensorFrame {
    cv::Mat rgb;    ///< CV_8UC3, R,G,B
    cv::Mat depth;  ///< CV_16UC1, units_per_m units per metre, 0 = invalid
};

SensorFrame apply_sensor(const RenderBuffers& render, const SensorConfig& config,
                         const io::Intrinsics& intrinsics, double units_per_m, uint64_t seed,
                         int frame, double t_s, int threads);

}  // namespace df::sim
