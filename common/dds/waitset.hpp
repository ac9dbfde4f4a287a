#pragma once
/// A waitset over readers' "new data" conditions, with a guard to wake it from another thread.
#include <vector>

#include "dds/entity.hpp"
#include "dds/participant.hpp"

namespace df::dds {

class WaitSet {
  public:
    static Result<WaitSet> create(const Participant& participant);

    /// Wakes wait() when the reader has samples not yet taken.
    Status attach_reader(dds_entity_t reader);
    /// Blocks until a reader has data, wake() is called, or the timeout passes.
    /// Returns the number of triggered conditions (0 = timeout).
    Result<int> wait(dds_duration_t timeout);
    /// Wakes a waiting thread (thread-safe; not async-signal-safe).
    void wake();

  private:
    WaitSet(Entity ws, Entity guard) : waitset_(std::move(ws)), guard_(std::move(guard)) {}
    Entity waitset_;
    Entity guard_;
    std::vector<Entity> conditions_;
};

}  // namespace df::dds
