#include "dds/qos.hpp"

namespace df::dds {

QosPtr make_qos(QosProfile profile, int32_t depth) {
    QosPtr q(dds_create_qos());
    int32_t default_depth = 16;
    dds_reliability_kind_t reliability = DDS_RELIABILITY_RELIABLE;
    switch (profile) {
        case QosProfile::kFrames:
            default_depth = 4;
            break;
        case QosProfile::kResults:
            default_depth = 16;
            break;
        case QosProfile::kStatus:
            default_depth = 64;
            break;
        case QosProfile::kTap:
            default_depth = 16;
            reliability = DDS_RELIABILITY_BEST_EFFORT;
            break;
    }
    dds_qset_history(q.get(), DDS_HISTORY_KEEP_LAST, depth > 0 ? depth : default_depth);
    dds_qset_reliability(q.get(), reliability, DDS_MSECS(100));
    dds_qset_durability(q.get(), DDS_DURABILITY_VOLATILE);
    dds_qset_liveliness(q.get(), DDS_LIVELINESS_AUTOMATIC, DDS_INFINITY);
    dds_qset_deadline(q.get(), DDS_INFINITY);
    return q;
}

const char* to_string(QosProfile profile) {
    switch (profile) {
        case QosProfile::kFrames:
            return "frames";
        case QosProfile::kResults:
            return "results";
        case QosProfile::kStatus:
            return "status";
        case QosProfile::kTap:
            return "tap";
    }
    return "?";
}

}  // namespace df::dds
