// One mapping per JSON format. A type's JSON form is written once, as a
// function `void map_json(json_io& io, T& value)` (found by argument-dependent
// lookup) that names its fields in order: the writer, the reader and the
// checker all walk it. The model is LLVM's yaml::MappingTraits<T>::mapping(IO&, T&).
//
//   void map_json(json_io& io, shard_spec& s) {
//       io.field("index", s.index);
//       io.field("count", s.count);
//       if (io.reading() && s.index > s.count) io.fail("index", "is beyond count");
//   }
//
// Writing builds an ordered JSON value, fields in the mapping's order.
// Reading checks each value's type as it takes it and throws input_error
// (file, line 0, FIELD, problem) with FIELD the value's path in the document,
// e.g. "state.audit.overall[0].verdicts[1] (false_miss)"; a mapping adds the
// checks only it can make (ranges, consistency) on what it has read, through
// io.fail. The path is formed only when a message needs it.
//
// Built in: whole numbers (std::size_t), strings, booleans, doubles (as exact
// hex floats, corpus_io's hex_float), std::optional<double> (a figure:
// json_number's spelling or null), any JSON value kept as it is, and vectors,
// arrays and string-keyed maps of mapped values.
#pragma once

#include <array>
#include <cstddef>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace rayverify {

// A finite double as a JSON number, ±inf and NaN as strings ("inf", "-inf", "nan").
nlohmann::ordered_json json_number(double x);
// json_number of a value, null for none.
nlohmann::ordered_json optional_number(const std::optional<double>& x);
// Room for `members` members in all in an object, before they are added.
// ordered_json keeps an object's members in a vector of (const name, value)
// pairs, and a vector that grows copies them, values and all (the const name
// makes a pair's move a copy): an object given large values (a column of a
// value per case, a report's sections) gets room for every member first, so
// that adding one copies none.
void reserve_members(nlohmann::ordered_json& object, std::size_t members);
// What json_number or optional_number wrote: a JSON number, "inf", "-inf" or
// "nan" (the value), null (nullopt inside); nullopt outside for anything else.
std::optional<std::optional<double>> number_from_json(const nlohmann::ordered_json& j);

class json_io;

template <class T>
concept json_mapped = requires(json_io& io, T& value) { map_json(io, value); };

class json_io {
public:
    using json = nlohmann::ordered_json;

    // Reads from `in`, which came from `file`; `context` is what the
    // mappings may consult (context<T>()), e.g. a header read before the body.
    // `line`: the line of `file` the document is on (0: the whole file).
    json_io(const json& in, const std::string& file, const void* context = nullptr, std::size_t line = 0)
        : in_(&in), file_(&file), context_(context), line_(line) {}
    // Writes to `out`.
    explicit json_io(json& out, const void* context = nullptr) : out_(&out), context_(context) {}

    bool reading() const { return in_ != nullptr; }
    template <class Context>
    const Context* context() const {
        return static_cast<const Context*>(context_);
    }
    // Where this value is, e.g. "state.audit.overall[0]"; "" at the top.
    std::string path() const;
    const std::string& file() const { return *file_; }

    // An input_error at this value (or its member `key`).
    [[noreturn]] void fail(const std::string& problem) const;
    [[noreturn]] void fail(std::string_view key, const std::string& problem) const;

    // A member that is a double written as a plain JSON number (a measurement
    // such as seconds, shown to people; it still reads back to the same double).
    void decimal_field(const char* key, double& value) {
        object_or_array(key, [&](json_io& child) { child.decimal(value); });
    }
    // A member that must be there.
    template <class T>
    void field(const char* key, T& value) {
        if (reading()) {
            json_io child(*this, key, member(key));
            child.value(value);
        } else {
            json_io child(*this, key, (*out_)[key]);
            child.value(value);
        }
    }
    // A member that is an array whose entries' paths carry a label (labelled below).
    template <class T, std::size_t N, class Label>
    void field(const char* key, std::array<T, N>& values, Label label) {
        object_or_array(key, [&](json_io& child) { child.labelled(values, label); });
    }
    // A member written when set, read when present (null is refused).
    template <class T>
    void optional_field(const char* key, std::optional<T>& value) {
        if (!reading()) {
            if (value) field(key, *value);
        } else if (has(key)) {
            field(key, value.emplace());
        }
    }
    // A member always there: null when unset.
    template <class T>
    void nullable_field(const char* key, std::optional<T>& value) {
        if (!reading()) {
            if (value)
                field(key, *value);
            else
                (*out_)[key] = nullptr;
        } else if (member(key).is_null()) {
            value.reset();
        } else {
            field(key, value.emplace());
        }
    }
    // A member that is an object whose fields `fields(json_io&)` maps (for a
    // group of fields that has no type of its own).
    template <class Fields>
    void object(const char* key, Fields fields) {
        object_or_array(key, [&](json_io& child) {
            if (child.reading() && !child.in_->is_object()) child.fail("is not a JSON object");
            if (!child.reading()) *child.out_ = json::object();
            fields(child);
        });
    }
    // True when reading and the member is there (use for members older writers left out).
    bool has(const char* key) const;

    // A value spelled as a name: `name_of(value)` writes it; `from_name(text)`
    // (an optional) reads it back; anything else is "'TEXT' is not EXPECTED".
    template <class T, class NameOf, class FromName>
    void name(T& value, NameOf name_of, FromName from_name, std::string_view expected) {
        if (!reading()) {
            *out_ = std::string(name_of(value));
            return;
        }
        std::string text;
        scalar(text);
        const auto read = from_name(text);
        if (!read) fail(quoted(text) + " is not " + std::string(expected));
        value = *read;
    }

    // An array whose entries' paths carry a label, e.g. "verdicts[1] (false_miss)".
    template <class T, std::size_t N, class Label>
    void labelled(std::array<T, N>& values, Label label) {
        sized(N);
        for (std::size_t i = 0; i < N; ++i) element(i, values[i], label(i));
    }

    // A whole value of any mapped type (the member functions above call it).
    template <class T>
    void value(T& v) {
        if constexpr (json_mapped<T>) {
            map_json(*this, v);  // a struct's first field checks that it is an object
        } else {
            scalar(v);
        }
    }
    // A mapped value or null (std::optional<double> is a figure: scalar's).
    template <class T>
        requires json_mapped<T>
    void value(std::optional<T>& v) {
        if (!reading()) {
            if (v)
                map_json(*this, *v);
            else
                *out_ = nullptr;
        } else if (in_->is_null()) {
            v.reset();
        } else {
            map_json(*this, v.emplace());
        }
    }
    template <class T>
    void value(std::vector<T>& values) {
        if (!reading()) {
            *out_ = json::array();
        } else {
            if (!in_->is_array()) fail("is " + shown(*in_) + ", expected an array");
            values.assign(in_->size(), T{});
        }
        for (std::size_t i = 0; i < values.size(); ++i) element(i, values[i]);
    }
    template <class T, std::size_t N>
    void value(std::array<T, N>& values) {
        sized(N);
        for (std::size_t i = 0; i < N; ++i) element(i, values[i]);
    }
    template <class T>
    void value(std::map<std::string, T>& values) {
        if (!reading()) {
            *out_ = json::object();
            for (auto& [key, v] : values) field(key.c_str(), v);
            return;
        }
        if (!in_->is_object()) fail("is not a JSON object");
        values.clear();
        for (const auto& [key, v] : in_->items()) field(key.c_str(), values[key]);
    }

    // The JSON shown in a message, cut at 60 characters.
    static std::string shown(const json& j);
    // Text of an input quoted in a message.
    static std::string quoted(std::string_view text);

private:
    json_io(const json_io& parent, const char* key, const json& in)
        : in_(&in), file_(parent.file_), context_(parent.context_), line_(parent.line_), parent_(&parent), key_(key) {}
    json_io(const json_io& parent, const char* key, json& out)
        : out_(&out), file_(parent.file_), context_(parent.context_), line_(parent.line_), parent_(&parent), key_(key) {}
    json_io(const json_io& parent, std::size_t index, std::string_view label, const json& in)
        : in_(&in), file_(parent.file_), context_(parent.context_), line_(parent.line_), parent_(&parent), index_(index),
          label_(label) {}
    json_io(const json_io& parent, std::size_t index, std::string_view label, json& out)
        : out_(&out), file_(parent.file_), context_(parent.context_), line_(parent.line_), parent_(&parent),
          index_(index), label_(label) {}

    template <class T>
    void element(std::size_t i, T& v, std::string_view label = {}) {
        if (reading()) {
            json_io child(*this, i, label, (*in_)[i]);
            child.value(v);
        } else {
            out_->push_back(nullptr);
            json_io child(*this, i, label, out_->back());
            child.value(v);
        }
    }
    template <class Fields>
    void object_or_array(const char* key, Fields fields) {
        if (reading()) {
            json_io child(*this, key, member(key));
            fields(child);
        } else {
            json_io child(*this, key, (*out_)[key]);
            fields(child);
        }
    }
    void sized(std::size_t n) const;
    const json& member(const char* key) const;

    void scalar(std::size_t& v);
    void scalar(std::string& v);
    void scalar(bool& v);
    void scalar(double& v);               // an exact hex float
    void scalar(std::optional<double>& v);  // a figure: json_number's spelling, or null
    void scalar(json& v);                 // any JSON, kept as it is
    void decimal(double& v);

    const json* in_ = nullptr;
    json* out_ = nullptr;
    const std::string* file_ = nullptr;
    const void* context_ = nullptr;
    std::size_t line_ = 0;
    const json_io* parent_ = nullptr;
    const char* key_ = nullptr;  // a member's key; else an element's index_ (and label_)
    std::size_t index_ = 0;
    std::string_view label_;
};

// `value` as JSON, through its mapping.
template <class T>
nlohmann::ordered_json to_json_mapped(const T& value, const void* context = nullptr) {
    nlohmann::ordered_json out;
    json_io io(out, context);
    io.value(const_cast<T&>(value));  // a mapping only reads its value when writing
    return out;
}

// `in` read through T's mapping; input_error naming `file` and the field on anything wrong.
template <class T>
T from_json_mapped(const nlohmann::ordered_json& in, const std::string& file, const void* context = nullptr,
                   std::size_t line = 0) {
    T value{};
    json_io io(in, file, context, line);
    io.value(value);
    return value;
}

}  // namespace rayverify
