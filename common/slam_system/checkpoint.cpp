#include "slam_system/checkpoint.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>

namespace df::slam {
namespace {

constexpr char kMagic[8] = {'D', 'F', 'S', 'L', 'A', 'M', 'C', 'K'};
constexpr uint32_t kVersion = 1;
constexpr size_t kHeaderBytes = sizeof kMagic + 4 + 8;
constexpr size_t kSurfelBytes = 11 * 4 + 2 * 4;  // 11 floats, 2 int32
constexpr size_t kPoseBytes = 8 * 8;

uint64_t fnv1a(const uint8_t* data, size_t n) {
    uint64_t h = 1469598103934665603ULL;
    for (size_t i = 0; i < n; ++i) {
        h ^= data[i];
        h *= 1099511628211ULL;
    }
    return h;
}

// The project targets little-endian hosts (x86-64, aarch64); values are copied as they are.
class Writer {
  public:
    template <typename T>
    void put(T v) {
        const auto* p = reinterpret_cast<const uint8_t*>(&v);
        bytes.insert(bytes.end(), p, p + sizeof v);
    }
    void put_pose(const Eigen::Isometry3d& pose) {
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) put(pose.linear()(r, c));
        for (int i = 0; i < 3; ++i) put(pose.translation()(i));
    }
    std::vector<uint8_t> bytes;
};

class Reader {
  public:
    Reader(const uint8_t* data, size_t size) : data_(data), size_(size) {}
    template <typename T>
    bool get(T* v) {
        if (size_ - pos_ < sizeof(T)) return false;
        std::memcpy(v, data_ + pos_, sizeof(T));
        pos_ += sizeof(T);
        return true;
    }
    bool get_pose(Eigen::Isometry3d* pose) {
        pose->setIdentity();
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c)
                if (!get(&pose->linear()(r, c))) return false;
        for (int i = 0; i < 3; ++i)
            if (!get(&pose->translation()(i))) return false;
        return true;
    }
    size_t left() const { return size_ - pos_; }

  private:
    const uint8_t* data_;
    size_t size_;
    size_t pos_ = 0;
};

std::vector<uint8_t> encode(const Checkpoint& c) {
    const SystemState& s = c.system;
    Writer w;
    w.put(c.last_seq);
    w.put(c.last_epoch);
    w.put(c.last_sensor_ns);
    w.put(s.frames);
    w.put(s.lost_frames);
    w.put(static_cast<int32_t>(s.map_time));
    w.put(static_cast<uint8_t>(s.started));
    w.put(static_cast<uint8_t>(s.lost));
    w.put(static_cast<int32_t>(s.input_width));
    w.put(static_cast<int32_t>(s.input_height));
    w.put_pose(s.world_T_camera);
    w.put_pose(s.last_motion);
    w.put(static_cast<uint64_t>(s.trajectory.size()));
    for (const io::StampedPose& p : s.trajectory) {
        w.put(p.stamp_s);
        for (int i = 0; i < 3; ++i) w.put(p.t(i));
        w.put(p.q.x());
        w.put(p.q.y());
        w.put(p.q.z());
        w.put(p.q.w());
    }
    w.put(static_cast<uint64_t>(s.surfels.size()));
    w.put(s.surfels_rejected_by_capacity);
    w.bytes.reserve(w.bytes.size() + s.surfels.size() * kSurfelBytes);
    for (const map::Surfel& m : s.surfels) {
        for (int i = 0; i < 3; ++i) w.put(m.position(i));
        for (int i = 0; i < 3; ++i) w.put(m.normal(i));
        for (int i = 0; i < 3; ++i) w.put(m.colour(i));
        w.put(m.radius);
        w.put(m.confidence);
        w.put(static_cast<int32_t>(m.init_frame));
        w.put(static_cast<int32_t>(m.last_seen_frame));
    }
    return std::move(w.bytes);
}

/// Decodes a payload whose hash matched; `what` is "<file>: " for messages.
Result<Checkpoint> decode(const uint8_t* data, size_t size, const std::string& what) {
    Reader r(data, size);
    Checkpoint c;
    SystemState& s = c.system;
    int32_t map_time = 0, width = 0, height = 0;
    uint8_t started = 0, lost = 0;
    const auto bad = [&](const std::string& why) {
        return error(StatusCode::kIoError, what + why);
    };
    if (!r.get(&c.last_seq) || !r.get(&c.last_epoch) || !r.get(&c.last_sensor_ns) ||
        !r.get(&s.frames) || !r.get(&s.lost_frames) || !r.get(&map_time) || !r.get(&started) ||
        !r.get(&lost) || !r.get(&width) || !r.get(&height) || !r.get_pose(&s.world_T_camera) ||
        !r.get_pose(&s.last_motion)) {
        return bad("payload ends inside the system state");
    }
    s.map_time = map_time;
    s.started = started != 0;
    s.lost = lost != 0;
    s.input_width = width;
    s.input_height = height;
    uint64_t poses = 0;
    if (!r.get(&poses) || poses > r.left() / kPoseBytes) {
        return bad("trajectory count " + std::to_string(poses) + " does not fit the file");
    }
    s.trajectory.resize(poses);
    for (io::StampedPose& p : s.trajectory) {
        double q[4] = {0, 0, 0, 1};
        (void)r.get(&p.stamp_s);
        for (int i = 0; i < 3; ++i) (void)r.get(&p.t(i));
        for (double& v : q) (void)r.get(&v);
        p.q = Eigen::Quaterniond(q[3], q[0], q[1], q[2]);
    }
    uint64_t surfels = 0;
    if (!r.get(&surfels) || !r.get(&s.surfels_rejected_by_capacity) ||
        surfels != r.left() / kSurfelBytes || r.left() % kSurfelBytes != 0) {
        return bad("surfel count " + std::to_string(surfels) + " does not match the " +
                   std::to_string(r.left()) + " bytes left");
    }
    s.surfels.resize(surfels);
    for (map::Surfel& m : s.surfels) {
        int32_t init = 0, seen = 0;
        for (int i = 0; i < 3; ++i) (void)r.get(&m.position(i));
        for (int i = 0; i < 3; ++i) (void)r.get(&m.normal(i));
        for (int i = 0; i < 3; ++i) (void)r.get(&m.colour(i));
        (void)r.get(&m.radius);
        (void)r.get(&m.confidence);
        (void)r.get(&init);
        (void)r.get(&seen);
        m.init_frame = init;
        m.last_seen_frame = seen;
    }
    return c;
}

Status write_all(int fd, const uint8_t* data, size_t n) {
    while (n > 0) {
        const ssize_t w = ::write(fd, data, n);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) return Status(StatusCode::kIoError, std::strerror(errno));
        data += w;
        n -= static_cast<size_t>(w);
    }
    return Status::ok();
}

}  // namespace

Status write_checkpoint(const std::string& file, const Checkpoint& checkpoint) {
    const std::vector<uint8_t> payload = encode(checkpoint);
    Writer head;
    for (char ch : kMagic) head.put(ch);
    head.put(kVersion);
    head.put(static_cast<uint64_t>(payload.size()));
    Writer tail;
    tail.put(fnv1a(payload.data(), payload.size()));

    const std::string tmp = file + ".tmp";
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) {
        return error(StatusCode::kIoError,
                     "cannot write checkpoint '" + tmp + "': " + std::strerror(errno));
    }
    Status s = write_all(fd, head.bytes.data(), head.bytes.size());
    if (s) s = write_all(fd, payload.data(), payload.size());
    if (s) s = write_all(fd, tail.bytes.data(), tail.bytes.size());
    if (s && ::fsync(fd) != 0) s = Status(StatusCode::kIoError, std::strerror(errno));
    if (::close(fd) != 0 && s) s = Status(StatusCode::kIoError, std::strerror(errno));
    if (s && std::rename(tmp.c_str(), file.c_str()) != 0) {
        s = Status(StatusCode::kIoError, std::string("rename: ") + std::strerror(errno));
    }
    if (!s) {
        std::remove(tmp.c_str());
        return error(StatusCode::kIoError,
                     "cannot write checkpoint '" + file + "': " + s.message());
    }
    return Status::ok();
}

Result<Checkpoint> read_checkpoint(const std::string& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) {
        if (access(file.c_str(), F_OK) != 0) {
            return error(StatusCode::kNotFound, "no checkpoint '" + file + "'");
        }
        return error(StatusCode::kIoError, "cannot read checkpoint '" + file + "'");
    }
    const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                     std::istreambuf_iterator<char>());
    const std::string what = "checkpoint '" + file + "': ";
    if (bytes.size() < kHeaderBytes || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0) {
        return error(StatusCode::kIoError, what + "not a SLAM checkpoint (no DFSLAMCK header)");
    }
    uint32_t version = 0;
    uint64_t length = 0;
    std::memcpy(&version, bytes.data() + sizeof kMagic, sizeof version);
    std::memcpy(&length, bytes.data() + sizeof kMagic + 4, sizeof length);
    if (version != kVersion) {
        return error(StatusCode::kIoError, what + "version " + std::to_string(version) +
                                               ", this build reads version " +
                                               std::to_string(kVersion));
    }
    const uint64_t expected = kHeaderBytes + length + 8;
    if (length > bytes.size() || bytes.size() != expected) {
        return error(StatusCode::kIoError,
                     what + (bytes.size() < expected ? "truncated: " : "trailing bytes: ") +
                         std::to_string(bytes.size()) + " bytes, the header says " +
                         std::to_string(expected));
    }
    const uint8_t* payload = bytes.data() + kHeaderBytes;
    uint64_t hash = 0;
    std::memcpy(&hash, payload + length, sizeof hash);
    if (hash != fnv1a(payload, length)) {
        return error(StatusCode::kIoError, what + "hash mismatch: the file is corrupt");
    }
    return decode(payload, length, what);
}

}  // namespace df::slam
