#pragma once
/// A parameter message of a service configuration (GeosegParams, InstanceParams, ...) onto the
/// struct generated from the same message (params/*.hpp): the fields set in the message replace
/// the struct's, the others keep their declared defaults. No field is named here: both sides come
/// from the one declaration in the .proto.
#include <google/protobuf/descriptor.h>
#include <google/protobuf/message.h>

#include <string>
#include <type_traits>
#include <vector>

#include "core/status.hpp"
#include "params/field_info.hpp"

namespace df::config {

namespace detail {

template <class T>
T get(const google::protobuf::Message& m, const google::protobuf::FieldDescriptor* f, int i) {
    const google::protobuf::Reflection* r = m.GetReflection();
    const bool rep = f->is_repeated();
    if constexpr (std::is_same_v<T, bool>) {
        return rep ? r->GetRepeatedBool(m, f, i) : r->GetBool(m, f);
    } else if constexpr (std::is_same_v<T, float>) {
        return rep ? r->GetRepeatedFloat(m, f, i) : r->GetFloat(m, f);
    } else if constexpr (std::is_same_v<T, double>) {
        return rep ? r->GetRepeatedDouble(m, f, i) : r->GetDouble(m, f);
    } else if constexpr (std::is_same_v<T, int>) {
        return rep ? r->GetRepeatedInt32(m, f, i) : r->GetInt32(m, f);
    } else if constexpr (std::is_same_v<T, unsigned>) {
        return rep ? r->GetRepeatedUInt32(m, f, i) : r->GetUInt32(m, f);
    } else if constexpr (std::is_same_v<T, std::string>) {
        return rep ? r->GetRepeatedString(m, f, i) : r->GetString(m, f);
    } else if constexpr (std::is_same_v<T, long long>) {
        return static_cast<T>(rep ? r->GetRepeatedInt64(m, f, i) : r->GetInt64(m, f));
    } else {
        static_assert(std::is_same_v<T, std::size_t>, "a parameter type the generator writes");
        return static_cast<T>(rep ? r->GetRepeatedUInt64(m, f, i) : r->GetUInt64(m, f));
    }
}

}  // namespace detail

/// Copies every field set in `message` onto `out` (nested messages onto nested structs).
/// kInvalidArgument when the struct has a field the message type lacks (they were generated
/// from different messages).
template <class S>
Status apply_params(const google::protobuf::Message& message, S* out) {
    const google::protobuf::Descriptor* d = message.GetDescriptor();
    const google::protobuf::Reflection* r = message.GetReflection();
    Status status = Status::ok();
    out->for_each_field([&](const params::FieldInfo& info, auto& value) {
        if (!status) return;
        const google::protobuf::FieldDescriptor* f = d->FindFieldByName(info.name);
        if (f == nullptr) {
            status =
                error(StatusCode::kInvalidArgument, d->full_name() + " has no field " + info.name);
            return;
        }
        using T = std::decay_t<decltype(value)>;
        if constexpr (params::detail::is_struct<T>::value) {
            if (r->HasField(message, f)) status = apply_params(r->GetMessage(message, f), &value);
        } else if constexpr (std::is_arithmetic_v<T> || std::is_same_v<T, std::string>) {
            if (r->HasField(message, f)) value = detail::get<T>(message, f, -1);
        } else {
            if (r->FieldSize(message, f) == 0) return;
            value.clear();
            for (int i = 0; i < r->FieldSize(message, f); ++i)
                value.push_back(detail::get<typename T::value_type>(message, f, i));
        }
    });
    return status;
}

}  // namespace df::config
