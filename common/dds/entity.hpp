#pragma once
/// RAII owner of one DDS entity handle: deleted (with its children) when the owner goes.
#include <dds/dds.h>

#include <utility>

namespace df::dds {

class Entity {
  public:
    Entity() = default;
    explicit Entity(dds_entity_t handle) : handle_(handle) {}
    ~Entity() { reset(); }
    Entity(const Entity&) = delete;
    Entity& operator=(const Entity&) = delete;
    Entity(Entity&& other) noexcept : handle_(std::exchange(other.handle_, 0)) {}
    Entity& operator=(Entity&& other) noexcept {
        if (this != &other) {
            reset();
            handle_ = std::exchange(other.handle_, 0);
        }
        return *this;
    }
    dds_entity_t get() const { return handle_; }
    bool valid() const { return handle_ > 0; }
    void reset() {
        if (handle_ > 0) dds_delete(handle_);
        handle_ = 0;
    }

  private:
    dds_entity_t handle_ = 0;
};

}  // namespace df::dds
