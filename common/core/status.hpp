#pragma once
/// Errors as values: Status for operations without a result, Result<T> for those with one.
/// A message says what failed and where (file, line, entity), so a user can act on it.
#include <optional>
#include <string>
#include <utility>
#include <variant>

namespace df {

enum class StatusCode {
    kOk = 0,
    kInvalidArgument,  ///< bad config, bad flag, malformed input line
    kNotFound,         ///< missing file, folder or entity
    kIoError,          ///< unreadable or corrupt file
    kUnavailable,      ///< peer or resource not there (yet)
    kTimeout,
    kResourceExhausted,  ///< e.g. no shared-memory loan left
    kEndOfStream,
    kInternal,
};

const char* to_string(StatusCode code);

class [[nodiscard]] Status {
  public:
    Status() = default;
    Status(StatusCode code, std::string message) : code_(code), message_(std::move(message)) {}
    static Status ok() { return {}; }

    bool is_ok() const { return code_ == StatusCode::kOk; }
    explicit operator bool() const { return is_ok(); }
    StatusCode code() const { return code_; }
    const std::string& message() const { return message_; }
    /// "<code>: <message>", or "ok".
    std::string to_string() const;
    /// Returns this status with "context: " put before the message.
    Status with_context(const std::string& context) const;

  private:
    StatusCode code_ = StatusCode::kOk;
    std::string message_;
};

inline Status error(StatusCode code, std::string message) { return {code, std::move(message)}; }

template <typename T>
class [[nodiscard]] Result {
  public:
    Result(T value) : value_(std::move(value)) {}  // NOLINT: implicit by design
    Result(Status status) : status_(std::move(status)) {
        if (status_.is_ok()) status_ = Status(StatusCode::kInternal, "Result built from ok status");
    }
    bool is_ok() const { return value_.has_value(); }
    explicit operator bool() const { return is_ok(); }
    const Status& status() const { return status_; }
    T& value() & { return *value_; }
    const T& value() const& { return *value_; }
    T&& value() && { return std::move(*value_); }
    T* operator->() { return &*value_; }
    const T* operator->() const { return &*value_; }
    T& operator*() & { return *value_; }
    const T& operator*() const& { return *value_; }
    T&& operator*() && { return std::move(*value_); }

  private:
    std::optional<T> value_;
    Status status_;
};

}  // namespace df

#define DF_RETURN_IF_ERROR(expr)                    \
    do {                                            \
        ::df::Status df_status_ = (expr);           \
        if (!df_status_.is_ok()) return df_status_; \
    } while (0)
