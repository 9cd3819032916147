#pragma once

#include <string>
#include <utility>

namespace cc {

/// What went wrong, as a code a caller can branch on.
enum class StatusCode {
    Ok = 0,
    InvalidArgument,   ///< a parameter or input datum is out of its documented range
    InvalidOperation,  ///< the call is not allowed in the object's current state
    NotConverged,      ///< an iterative solve stopped at its iteration cap
    NumericalFailure,  ///< NaN/Inf appeared or a factorisation failed; state was restored
};

/// Result of an operation: a code plus a message that names what failed and where.
/// Cheap when Ok (empty string). Internal code returns Status instead of throwing.
class [[nodiscard]] Status {
public:
    Status() = default;
    static Status ok() { return {}; }
    static Status error(StatusCode code, std::string message) {
        Status s;
        s.mCode = code;
        s.mMessage = std::move(message);
        return s;
    }
    static Status invalidArgument(std::string message) {
        return error(StatusCode::InvalidArgument, std::move(message));
    }

    bool isOk() const { return mCode == StatusCode::Ok; }
    explicit operator bool() const { return isOk(); }
    StatusCode code() const { return mCode; }
    const std::string& message() const { return mMessage; }

private:
    StatusCode mCode = StatusCode::Ok;
    std::string mMessage;
};

/// A value or the Status that explains why there is none.
template <typename T>
class [[nodiscard]] Result {
public:
    Result(T value) : mValue(std::move(value)) {}
    Result(Status status) : mStatus(std::move(status)) {}

    bool isOk() const { return mStatus.isOk(); }
    const Status& status() const { return mStatus; }
    T& value() & { return mValue; }
    const T& value() const& { return mValue; }
    T&& value() && { return std::move(mValue); }

private:
    Status mStatus;
    T mValue{};
};

} // namespace cc
