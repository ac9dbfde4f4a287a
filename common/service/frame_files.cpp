#include "service/frame_files.hpp"

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "io/tum/tum_folder.hpp"

namespace df::service {

void add_frame_file_flags(CLI::App& app, FrameFileFlags* f) {
    app.add_option("--color", f->color,
                   "command-line mode (no DDS): the frame's colour picture (8-bit)");
    app.add_option("--depth", f->depth,
                   "command-line mode (no DDS): the frame's depth picture (16-bit, raw units)");
    app.add_option("--preset", f->preset, "with --depth: camera intrinsics, fr1, fr2, fr3, 7scenes")
        ->capture_default_str();
    app.add_option("--depth-scale", f->depth_units_per_m,
                   "with --depth: depth units per metre (TUM 5000, OpenNI and 7-Scenes 1000)")
        ->capture_default_str()
        ->check(CLI::Range(1.0, 1e6));
    app.add_option("--out", f->out_dir,
                   "with --depth: folder for the pictures written ('' writes none)")
        ->capture_default_str();
}

Result<io::RgbdImage> read_frame_files(const FrameFileFlags& f) {
    if (f.depth.empty()) {
        return error(StatusCode::kInvalidArgument, "--color needs --depth (the frame's depth)");
    }
    auto intrinsics = io::intrinsics_preset(f.preset);
    if (!intrinsics) return intrinsics.status().with_context("--preset");
    auto image = io::read_rgbd_files(f.color, f.depth, *intrinsics, f.depth_units_per_m);
    if (!image) return image.status();
    DF_RETURN_IF_ERROR(io::check_intrinsics(*intrinsics, image->depth.cols, image->depth.rows,
                                            "--preset " + f.preset));
    return image;
}

Result<std::string> write_picture(const FrameFileFlags& f, const std::string& suffix,
                                  const cv::Mat& rgb) {
    cv::Mat bgr;
    cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
    return write_image(f, suffix, bgr);
}

Result<std::string> write_image(const FrameFileFlags& f, const std::string& suffix,
                                const cv::Mat& image) {
    if (f.out_dir.empty()) return std::string();
    std::error_code ec;
    std::filesystem::create_directories(f.out_dir, ec);
    const std::string path =
        (std::filesystem::path(f.out_dir) /
         (std::filesystem::path(f.depth).stem().string() + "_" + suffix + ".png"))
            .string();
    bool written = false;
    try {
        written = cv::imwrite(path, image);
    } catch (const cv::Exception&) {
        written = false;
    }
    if (!written) return error(StatusCode::kIoError, path + ": cannot write the picture");
    return path;
}

}  // namespace df::service
