#include "dds/waitset.hpp"

#include "dds/dds_error.hpp"

namespace df::dds {

Result<WaitSet> WaitSet::create(const Participant& participant) {
    const dds_entity_t ws = dds_create_waitset(participant.get());
    if (ws < 0) return check(ws, "creating waitset");
    const dds_entity_t guard = dds_create_guardcondition(participant.get());
    if (guard < 0) {
        dds_delete(ws);
        return check(guard, "creating guard condition");
    }
    WaitSet w{Entity(ws), Entity(guard)};
    DF_RETURN_IF_ERROR(check(dds_waitset_attach(ws, guard, guard), "attaching guard condition"));
    return w;
}

Status WaitSet::attach_reader(dds_entity_t reader) {
    const dds_entity_t cond = dds_create_readcondition(
        reader, DDS_NOT_READ_SAMPLE_STATE | DDS_ANY_VIEW_STATE | DDS_ANY_INSTANCE_STATE);
    if (cond < 0) return check(cond, "creating read condition");
    conditions_.emplace_back(cond);
    return check(dds_waitset_attach(waitset_.get(), cond, reader), "attaching reader to waitset");
}

Result<int> WaitSet::wait(dds_duration_t timeout) {
    const dds_return_t n = dds_waitset_wait(waitset_.get(), nullptr, 0, timeout);
    if (n < 0) return check(n, "waiting on waitset");
    bool triggered = false;
    dds_take_guardcondition(guard_.get(), &triggered);
    return static_cast<int>(n);
}

void WaitSet::wake() { dds_set_guardcondition(guard_.get(), true); }

}  // namespace df::dds
