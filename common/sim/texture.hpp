#pragma once
/// Surface appearance: procedural patterns (sized in metres, so they look the same at any
/// resolution) and photo decals (the darknet sample photos) on the faces of primitives.
#include <Eigen/Core>
#include <map>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "sim/shapes.hpp"

namespace df::sim {

using Rgb = Eigen::Vector3d;  ///< colour, channels R, G, B in 0..1

enum class Pattern {
    kSolid,    ///< colour a
    kChecker,  ///< squares of `scale` metres, a and b
    kNoise,    ///< smooth noise between a and b, feature size `scale`
    kPlanks,   ///< wooden floor: planks `scale` wide, six times as long, tones between a and b
    kTiles,    ///< square tiles of `scale` metres (a) with grout lines (b)
    kStripes,  ///< stripes of period `scale` across u (or v), a and b
    kPanel,    ///< face filled with a inside a border of `scale` metres in b (windows, screens)
    kRings,    ///< concentric rings of `scale` metres around the face centre (hub caps, targets)
};

struct Texture {
    Pattern pattern = Pattern::kSolid;
    Rgb a = Rgb(0.6, 0.6, 0.6), b = Rgb(0.3, 0.3, 0.3);
    double scale = 0.1;         ///< metres
    bool along_v = false;       ///< kStripes: stripes run across v instead of u
    double grain = 0.06;        ///< relative amplitude of a fine mottling on every pattern
    double grain_scale = 0.03;  ///< metres
};

/// A photo stuck on a shape: the rectangle centre +- half_width * right +- half_height * up in the
/// shape's local frame, seen from the side right x up points to. Image rows go down along -up.
struct Decal {
    std::string photo;                     ///< name of the photo (for sequence.json)
    std::shared_ptr<const cv::Mat> image;  ///< CV_8UC3, R,G,B; null = photo missing (grey fill)
    Vec3 centre = Vec3::Zero(), right = Vec3::UnitY(), up = Vec3::UnitZ();
    double half_width = 0.2, half_height = 0.15;
    double border = 0;    ///< frame around the photo, metres
    double depth = 0.05;  ///< only surface points within this distance of the decal's plane
    Rgb border_colour = Rgb(0.1, 0.1, 0.1);
};

struct Material {
    std::string name;
    Texture texture;
    std::vector<Decal> decals;
    double depth_dropout = 0;  ///< chance a pixel of it gives no depth (dark glass, black plastic)
    double emission = 0;       ///< light it gives off itself (lamps), added as emission * albedo
};

/// A material with a pattern and colours (helper for scene builders).
Material make_material(const std::string& name, Pattern pattern, const Rgb& a,
                       const Rgb& b = Rgb(0.3, 0.3, 0.3), double scale = 0.1, double grain = 0.06);

/// Albedo of a material at local point p of `shape` with surface description s. `seed` varies the
/// procedural noise (scene seed mixed with the material index).
Rgb albedo(const Material& material, const Vec3& p, const SurfacePoint& s, uint64_t seed);

/// Smooth value noise in [0, 1] (3 octaves).
double fbm(uint64_t seed, double x, double y);

/// The darknet sample photos, loaded once (R,G,B). A missing photo gives a null image.
class PhotoLibrary {
  public:
    /// Loads dog, horses, person, kite, giraffe, eagle and scream from `folder` (*.jpg).
    explicit PhotoLibrary(const std::string& folder);
    std::shared_ptr<const cv::Mat> get(const std::string& name) const;
    const std::string& folder() const { return folder_; }
    /// Names of the photos that could not be read.
    std::vector<std::string> missing() const;

  private:
    std::string folder_;
    std::map<std::string, std::shared_ptr<const cv::Mat>> photos_;
};

}  // namespace df::sim
