#pragma once
/// Typed writer. A sample is obtained as a Loan: from iceoryx shared memory when the topic can
/// be loaned (fixed-size type, shm transport, compatible QoS), else from a heap buffer that is
/// copied on write. Either way the caller fills the sample in place and calls write().
#include <dds/ddsc/dds_loan_api.h>

#include <cstring>
#include <memory>
#include <string>
#include <utility>

#include "dds/dds_error.hpp"
#include "dds/endpoint.hpp"
#include "dds/msg_types.hpp"

namespace df::dds {

template <typename T>
class Writer;

/// Cyclone 0.10 tracks at most 8 open loans per writer (MAX_PUB_LOANS); a 9th loan could never
/// be returned and would leak its chunk, so a writer hands out at most this many at once.
inline constexpr int kMaxOpenLoans = 8;

/// A sample to fill and write. Returned to the writer (unwritten) when destroyed.
template <typename T>
class Loan {
  public:
    Loan(Loan&& o) noexcept
        : writer_(std::exchange(o.writer_, 0)),
          sample_(std::exchange(o.sample_, nullptr)),
          heap_(std::move(o.heap_)),
          open_(std::exchange(o.open_, nullptr)) {}
    Loan& operator=(Loan&&) = delete;
    Loan(const Loan&) = delete;
    ~Loan() {
        if (sample_ != nullptr && !heap_ && writer_ > 0) {
            void* p = sample_;
            dds_return_loan(writer_, &p, 1);
        }
        release();
    }
    T* get() { return sample_; }
    T& operator*() { return *sample_; }
    T* operator->() { return sample_; }
    /// True when the sample lives in shared memory (zero-copy write).
    bool shared_memory() const { return !heap_; }

  private:
    friend class Writer<T>;
    Loan(dds_entity_t writer, T* shm_sample, int* open)
        : writer_(writer), sample_(shm_sample), open_(open) {}
    explicit Loan(std::unique_ptr<T> heap) : sample_(heap.get()), heap_(std::move(heap)) {}
    void release() {
        if (open_ != nullptr) --*open_;
        open_ = nullptr;
    }
    dds_entity_t writer_ = 0;
    T* sample_ = nullptr;
    std::unique_ptr<T> heap_;
    int* open_ = nullptr;  // the writer's count of open shared-memory loans
};

template <typename T>
class Writer {
  public:
    static Result<Writer> create(const Participant& participant, const std::string& topic,
                                 EndpointOptions options = {MsgTraits<T>::kProfile}) {
        auto w = create_writer(participant, MsgTraits<T>::descriptor(), topic, options);
        if (!w) return w.status();
        const bool loans = options.allow_loans && dds_is_loan_available(w->get());
        return Writer(std::move(*w), topic, loans);
    }

    /// A sample to fill. Falls back to a heap sample when no shared-memory chunk is available
    /// (pool exhausted, kMaxOpenLoans open, or loans not possible); never aborts.
    /// Not thread-safe: one thread per writer.
    Result<Loan<T>> loan() {
        if (loans_) {
            void* p = nullptr;
            if (*open_loans_ < kMaxOpenLoans &&
                dds_loan_sample(writer_.get(), &p) == DDS_RETCODE_OK && p != nullptr) {
                ++*open_loans_;
                return Loan<T>(writer_.get(), static_cast<T*>(p), open_loans_.get());
            }
            ++loan_failures_;
        }
        auto heap = std::make_unique<T>();
        std::memset(static_cast<void*>(heap.get()), 0, sizeof(T));
        return Loan<T>(std::move(heap));
    }

    /// Publishes a loaned sample; the loan is consumed either way.
    Status write(Loan<T>&& loan) {
        Loan<T> l(std::move(loan));
        if (l.sample_ == nullptr)
            return Status(StatusCode::kInvalidArgument, "write of an empty loan");
        const dds_return_t rc = dds_write(writer_.get(), l.sample_);
        if (!l.heap_)
            l.sample_ = nullptr;  // ownership passed to DDS (also on error, as Cyclone frees it)
        l.release();
        return check(rc, "writing to '" + topic_ + "'");
    }

    /// Publishes a copy of a sample.
    Status write_copy(const T& sample) {
        return check(dds_write(writer_.get(), &sample), "writing to '" + topic_ + "'");
    }

    dds_entity_t get() const { return writer_.get(); }
    const std::string& topic() const { return topic_; }
    bool loans_shared_memory() const { return loans_; }
    uint64_t loan_failures() const { return loan_failures_; }
    uint32_t matched_readers() const { return dds::matched_readers(writer_.get()); }

  private:
    Writer(Entity w, std::string topic, bool loans)
        : writer_(std::move(w)), topic_(std::move(topic)), loans_(loans) {}
    Entity writer_;
    std::string topic_;
    bool loans_ = false;
    uint64_t loan_failures_ = 0;
    std::unique_ptr<int> open_loans_ = std::make_unique<int>(0);  // stable address for Loans
};

}  // namespace df::dds
