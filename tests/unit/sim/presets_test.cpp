// Every preset builds and shows what it promises; moving things never run into each other.
#include <gtest/gtest.h>

#include <map>
#include <set>

#include "sim/person.hpp"
#include "sim/sequence.hpp"

namespace df::sim {
namespace {

struct Seen {
    std::map<std::string, int> frames_visible;  ///< object name -> frames with >= min_px pixels
    int frames_with_two_persons = 0;
    int frames_with_all_kinds = 0;
};

/// Renders every `step`-th frame of the preset at 160x120 (noise-free) and counts what is seen.
Seen look_at_preset(const Sequence& s, int step, int min_px = 40) {
    Seen seen;
    for (int i = 0; i < s.frames; i += step) {
        const RenderBuffers b = render_frame(s, i, 2);
        std::vector<int> count(s.scene.objects.size() + 1, 0);
        for (int y = 0; y < b.instance.rows; ++y)
            for (int x = 0; x < b.instance.cols; ++x) ++count[b.instance.at<uint16_t>(y, x)];
        int persons = 0;
        std::set<ObjectKind> kinds;
        for (size_t k = 0; k < s.scene.objects.size(); ++k) {
            if (count[k + 1] < min_px) continue;
            ++seen.frames_visible[s.scene.objects[k].name];
            if (s.scene.objects[k].class_name == "person") ++persons;
            kinds.insert(s.scene.objects[k].kind);
        }
        if (persons >= 2) ++seen.frames_with_two_persons;
        if (kinds.size() == 3) ++seen.frames_with_all_kinds;
    }
    return seen;
}

Sequence preset(const std::string& name) {
    PresetOptions o;
    o.width = 160;
    o.height = 120;
    auto s = make_sequence(name, o);
    EXPECT_TRUE(s.is_ok()) << s.status().to_string();
    return std::move(s).value();
}

TEST(SimPresets, AllBuildWithTheCameraInsideTheRoom) {
    ASSERT_GE(presets().size(), 9u);
    for (const PresetInfo& info : presets()) {
        const Sequence s = preset(info.name);
        EXPECT_EQ(s.frames, info.default_frames);
        for (int i = 0; i < s.frames; i += 10) {
            const Vec3 c = frame_state(s, i).world_T_camera.translation();
            EXPECT_TRUE((c.array() > s.scene.room.lo.array() + 0.2).all() &&
                        (c.array() < s.scene.room.hi.array() - 0.2).all())
                << info.name << " frame " << i;
        }
    }
    EXPECT_FALSE(make_sequence("walking_nowhere", PresetOptions{}).is_ok());
}

TEST(SimPresets, WalkingPresetsShowTwoPersonsWalkingThroughTheView) {
    for (const char* name :
         {"walking_static", "walking_xyz", "walking_rpy", "walking_halfsphere"}) {
        const Sequence s = preset(name);
        const Seen seen = look_at_preset(s, 6);
        std::printf("%s: frames with two persons %d of %d\n", name, seen.frames_with_two_persons,
                    s.frames / 6);
        EXPECT_GT(seen.frames_with_two_persons, 3) << name;
        // Walking: the root of each person moves metres over the sequence.
        for (size_t k = 0; k < 2; ++k) {
            const Vec3 a = s.scene.objects[k].motion->at(0).world_T_object.translation();
            double travelled = 0;
            for (int i = 1; i < s.frames; ++i) {
                travelled = std::max(
                    travelled,
                    (s.scene.objects[k].motion->at(i / s.fps).world_T_object.translation() - a)
                        .norm());
            }
            EXPECT_GT(travelled, 2.0) << name << " person " << k;
        }
    }
}

TEST(SimPresets, SittingPresetsShowTwoPersonsMovingALittle) {
    for (const char* name :
         {"sitting_static", "sitting_xyz", "sitting_rpy", "sitting_halfsphere"}) {
        const Sequence s = preset(name);
        const Seen seen = look_at_preset(s, 10);
        EXPECT_GT(seen.frames_with_two_persons, 10) << name;
        for (size_t k = 0; k < 2; ++k) {
            const Motion& m = *s.scene.objects[k].motion;
            const Vec3 root0 = m.at(0).world_T_object.translation();
            double root_move = 0, hand_move = 0;
            const Vec3 hand0 = m.at(0).object_T_bone[kLowerArmR].translation();
            for (int i = 0; i < s.frames; ++i) {
                const ObjectState st = m.at(i / s.fps);
                root_move = std::max(root_move, (st.world_T_object.translation() - root0).norm());
                hand_move = std::max(hand_move,
                                     (st.object_T_bone[kLowerArmR].translation() - hand0).norm());
            }
            EXPECT_LT(root_move, 0.01) << name << ": a sitting person stays on the chair";
            EXPECT_GT(hand_move, 0.05) << name << ": ...but gestures";
        }
    }
}

TEST(SimPresets, Room4HasACarThatDrivesStopsAndDrivesAgain) {
    const Sequence s = preset("room4");
    size_t car = 0;
    while (car < s.scene.objects.size() && s.scene.objects[car].class_name != "car") ++car;
    ASSERT_LT(car, s.scene.objects.size());
    EXPECT_EQ(s.scene.objects[car].class_id, 2);
    EXPECT_EQ(s.scene.objects[car].kind, ObjectKind::kRigid);
    const Seen seen = look_at_preset(s, 10);
    EXPECT_GT(seen.frames_visible.count("car_1") ? seen.frames_visible.at("car_1") : 0, 5);
    int stopped = 0, moving = 0;
    double range = 0, turned_standing = 0;
    const Motion& m = *s.scene.objects[car].motion;
    const Vec3 start = m.at(0).world_T_object.translation();
    for (int i = 1; i < 30 * 60; ++i) {
        const Iso3 a = m.at((i - 1) / s.fps).world_T_object, b = m.at(i / s.fps).world_T_object;
        const bool standing = (b.translation() - a.translation()).norm() < 1e-6;
        if (i < s.frames) (standing ? stopped : moving)++;
        range = std::max(range, (b.translation() - start).norm());
        // A car does not turn on the spot (beyond a hair at the loop's seam).
        if (standing)
            turned_standing += Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
    }
    std::printf("room4 car: turned %.3f rad standing still over a minute\n", turned_standing);
    EXPECT_LT(turned_standing, 0.01) << "radians turned standing still over a minute";
    EXPECT_GT(range, 2.0);
    EXPECT_GT(stopped, 20);
    EXPECT_GT(moving, 100);
}

TEST(SimPresets, DefaultShowsEveryKindOfInstanceAndAMovingCamera) {
    const Sequence s = preset("default");
    std::set<ObjectKind> kinds;
    for (const DynamicObject& o : s.scene.objects) kinds.insert(o.kind);
    EXPECT_EQ(kinds.size(), 3u);
    const Seen seen = look_at_preset(s, 5);
    std::printf("default: frames with rigid + non-rigid + unknown visible: %d of %d\n",
                seen.frames_with_all_kinds, s.frames / 5);
    EXPECT_GT(seen.frames_with_all_kinds, 5);
    const Vec3 c0 = frame_state(s, 0).world_T_camera.translation();
    const Vec3 c1 = frame_state(s, s.frames - 1).world_T_camera.translation();
    EXPECT_GT((c1 - c0).norm(), 0.05);
}

/// Moving things keep apart: the distance between two objects' ground positions stays above the
/// sum of their footprint radii over a minute.
TEST(SimPresets, MovingThingsNeverRunIntoEachOther) {
    auto radius = [](const DynamicObject& o) {
        if (o.class_name == "car") return 0.45;  // half width + mirror; crossing paths are lanes
        if (o.class_name == "person") return 0.25;
        if (o.class_name == "suitcase") return 0.25;
        return 0.45;  // the drum, rolling across its axis
    };
    for (const PresetInfo& info : presets()) {
        const Sequence s = preset(info.name);
        for (int i = 0; i < 30 * 60; i += 2) {
            const FrameState st = frame_state(s, i);
            for (size_t a = 0; a < st.objects.size(); ++a)
                for (size_t b = a + 1; b < st.objects.size(); ++b) {
                    const double d = (st.objects[a].world_T_object.translation() -
                                      st.objects[b].world_T_object.translation())
                                         .head<2>()
                                         .norm();
                    ASSERT_GT(d, radius(s.scene.objects[a]) + radius(s.scene.objects[b]) - 0.1)
                        << info.name << " t " << i / 30.0 << " s: " << s.scene.objects[a].name
                        << " and " << s.scene.objects[b].name;
                }
        }
    }
}

}  // namespace
}  // namespace df::sim
