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
// Version 2 adds the object maps after the static surfels; version 3 each map's mover evidence
// (objects/mover_evidence.hpp) after its body motion, version 4 the evidence's settled count
// after it. Versions 1 (no object maps), 2 (maps not yet proven moving) and 3 (maps not yet
// settled) are still read.
constexpr uint32_t kVersion = 4;
constexpr size_t kHeaderBytes = sizeof kMagic + 4 + 8;
constexpr size_t kSurfelBytes = 11 * 4 + 2 * 4;  // 11 floats, 2 int32
constexpr size_t kPoseBytes = 8 * 8;
// The fixed part of one object map: ids, score, state, frame counts, two poses, two counts.
constexpr size_t kObjectBytes = 4 + 4 + 4 + 1 + 3 * 8 + 4 + 2 * 12 * 8 + 8 + 2 * 8;

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
    void put_trajectory(const std::vector<io::StampedPose>& trajectory) {
        put(static_cast<uint64_t>(trajectory.size()));
        for (const io::StampedPose& p : trajectory) {
            put(p.stamp_s);
            for (int i = 0; i < 3; ++i) put(p.t(i));
            put(p.q.x());
            put(p.q.y());
            put(p.q.z());
            put(p.q.w());
        }
    }
    void put_surfels(const std::vector<map::Surfel>& surfels, uint64_t rejected) {
        put(static_cast<uint64_t>(surfels.size()));
        put(rejected);
        bytes.reserve(bytes.size() + surfels.size() * kSurfelBytes);
        for (const map::Surfel& m : surfels) {
            for (int i = 0; i < 3; ++i) put(m.position(i));
            for (int i = 0; i < 3; ++i) put(m.normal(i));
            for (int i = 0; i < 3; ++i) put(m.colour(i));
            put(m.radius);
            put(m.confidence);
            put(static_cast<int32_t>(m.init_frame));
            put(static_cast<int32_t>(m.last_seen_frame));
        }
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
    /// A trajectory; false when its count does not fit what is left.
    bool get_trajectory(std::vector<io::StampedPose>* trajectory, uint64_t* count) {
        if (!get(count) || *count > left() / kPoseBytes) return false;
        trajectory->resize(*count);
        for (io::StampedPose& p : *trajectory) {
            double q[4] = {0, 0, 0, 1};
            (void)get(&p.stamp_s);
            for (int i = 0; i < 3; ++i) (void)get(&p.t(i));
            for (double& v : q) (void)get(&v);
            p.q = Eigen::Quaterniond(q[3], q[0], q[1], q[2]);
        }
        return true;
    }
    /// Surfels; false when their count does not fit what is left (`exact`: is all that is left).
    bool get_surfels(std::vector<map::Surfel>* surfels, uint64_t* rejected, uint64_t* count,
                     bool exact) {
        if (!get(count) || !get(rejected)) return false;
        if (exact ? (*count != left() / kSurfelBytes || left() % kSurfelBytes != 0)
                  : *count > left() / kSurfelBytes)
            return false;
        surfels->resize(*count);
        for (map::Surfel& m : *surfels) {
            int32_t init = 0, seen = 0;
            for (int i = 0; i < 3; ++i) (void)get(&m.position(i));
            for (int i = 0; i < 3; ++i) (void)get(&m.normal(i));
            for (int i = 0; i < 3; ++i) (void)get(&m.colour(i));
            (void)get(&m.radius);
            (void)get(&m.confidence);
            (void)get(&init);
            (void)get(&seen);
            m.init_frame = init;
            m.last_seen_frame = seen;
        }
        return true;
    }

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
    w.put_trajectory(s.trajectory);
    w.put_surfels(s.surfels, s.surfels_rejected_by_capacity);
    const objects::ObjectMapsState& o = s.objects;
    w.put(static_cast<int32_t>(o.next_id));
    for (uint64_t v : {o.counters.created, o.counters.revived, o.counters.retired,
                       o.counters.refused_by_cap, o.counters.surfels_rejected_by_capacity})
        w.put(v);
    w.put(static_cast<uint64_t>(o.objects.size()));
    for (const objects::ObjectMapState& m : o.objects) {
        w.put(static_cast<int32_t>(m.id));
        w.put(static_cast<int32_t>(m.class_id));
        w.put(m.score);
        w.put(static_cast<uint8_t>(m.state == objects::ObjectState::kRetired));
        w.put(m.first_frame);
        w.put(m.last_seen_frame);
        w.put(m.frames_tracked);
        w.put(static_cast<int32_t>(m.frames_lost));
        w.put_pose(m.world_T_object);
        w.put_pose(m.body_motion);
        w.put(static_cast<uint8_t>(m.mover.moving));
        w.put(static_cast<uint8_t>(m.mover.anchored));
        w.put_pose(m.mover.anchor);
        w.put(static_cast<int32_t>(m.mover.frames_over));
        w.put_pose(m.mover.still_since);
        w.put(static_cast<int32_t>(m.mover.frames_within));
        w.put(static_cast<int32_t>(m.mover.times_proven));
        w.put(static_cast<int32_t>(m.mover.frames_settled));
        w.put_trajectory(m.trajectory);
        w.put_surfels(m.surfels, m.surfels_rejected_by_capacity);
    }
    return std::move(w.bytes);
}

/// Decodes a payload whose hash matched; `what` is "<file>: " for messages.
Result<Checkpoint> decode(const uint8_t* data, size_t size, uint32_t version,
                          const std::string& what) {
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
    if (!r.get_trajectory(&s.trajectory, &poses)) {
        return bad("trajectory count " + std::to_string(poses) + " does not fit the file");
    }
    uint64_t surfels = 0;
    const size_t before = r.left();
    if (!r.get_surfels(&s.surfels, &s.surfels_rejected_by_capacity, &surfels, version == 1)) {
        return bad("surfel count " + std::to_string(surfels) + " does not match the " +
                   std::to_string(before) + " bytes left");
    }
    if (version == 1) return c;
    objects::ObjectMapsState& o = s.objects;
    int32_t next_id = 1;
    uint64_t count = 0;
    if (!r.get(&next_id) || !r.get(&o.counters.created) || !r.get(&o.counters.revived) ||
        !r.get(&o.counters.retired) || !r.get(&o.counters.refused_by_cap) ||
        !r.get(&o.counters.surfels_rejected_by_capacity) || !r.get(&count) ||
        count > r.left() / kObjectBytes) {
        return bad("object map count " + std::to_string(count) + " does not fit the file");
    }
    o.next_id = next_id;
    o.objects.resize(count);
    for (objects::ObjectMapState& m : o.objects) {
        int32_t id = 0, class_id = 0, frames_lost = 0;
        uint8_t retired = 0;
        uint64_t n = 0, rejected = 0;
        if (!r.get(&id) || !r.get(&class_id) || !r.get(&m.score) || !r.get(&retired) ||
            !r.get(&m.first_frame) || !r.get(&m.last_seen_frame) || !r.get(&m.frames_tracked) ||
            !r.get(&frames_lost) || !r.get_pose(&m.world_T_object) || !r.get_pose(&m.body_motion)) {
            return bad("payload ends inside object map " + std::to_string(id));
        }
        m.id = id;
        m.class_id = class_id;
        m.frames_lost = frames_lost;
        m.state = retired ? objects::ObjectState::kRetired : objects::ObjectState::kActive;
        if (version >= 3) {
            uint8_t moving = 0, anchored = 0;
            int32_t over = 0, within = 0, proven = 0;
            if (!r.get(&moving) || !r.get(&anchored) || !r.get_pose(&m.mover.anchor) ||
                !r.get(&over) || !r.get_pose(&m.mover.still_since) || !r.get(&within) ||
                !r.get(&proven)) {
                return bad("payload ends inside object map " + std::to_string(id) +
                           "'s mover evidence");
            }
            m.mover.moving = moving != 0;
            m.mover.anchored = anchored != 0;
            m.mover.frames_over = over;
            m.mover.frames_within = within;
            m.mover.times_proven = proven;
        }
        if (version >= 4) {
            int32_t settled = 0;
            if (!r.get(&settled)) {
                return bad("payload ends inside object map " + std::to_string(id) +
                           "'s mover evidence");
            }
            m.mover.frames_settled = settled;
        }
        if (!r.get_trajectory(&m.trajectory, &n)) {
            return bad("object map " + std::to_string(id) + ": trajectory count " +
                       std::to_string(n) + " does not fit the file");
        }
        if (!r.get_surfels(&m.surfels, &rejected, &n, false)) {
            return bad("object map " + std::to_string(id) + ": surfel count " + std::to_string(n) +
                       " does not fit the file");
        }
        m.surfels_rejected_by_capacity = rejected;
    }
    if (r.left() != 0) return bad(std::to_string(r.left()) + " bytes after the last object map");
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
    if (version < 1 || version > kVersion) {
        return error(StatusCode::kIoError, what + "version " + std::to_string(version) +
                                               ", this build reads versions 1 to " +
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
    return decode(payload, length, version, what);
}

}  // namespace df::slam
