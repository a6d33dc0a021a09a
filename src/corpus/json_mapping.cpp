#include "corpus/json_mapping.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "core/input_error.h"
#include "corpus/corpus_io.h"

namespace rayverify {

using json = nlohmann::ordered_json;

json json_number(double x) {
    if (std::isnan(x)) return "nan";
    if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
    return x;
}

json optional_number(const std::optional<double>& x) { return x ? json_number(*x) : json(nullptr); }

void reserve_members(json& object, std::size_t members) { object.get_ref<json::object_t&>().reserve(members); }

std::optional<std::optional<double>> number_from_json(const json& j) {
    using value = std::optional<double>;
    if (j.is_null()) return value();
    if (j.is_number()) return value(j.get<double>());
    if (j == "inf") return value(std::numeric_limits<double>::infinity());
    if (j == "-inf") return value(-std::numeric_limits<double>::infinity());
    if (j == "nan") return value(std::numeric_limits<double>::quiet_NaN());
    return std::nullopt;
}

std::string json_io::path() const {
    if (parent_ == nullptr) return "";
    std::string at = parent_->path();
    if (key_ != nullptr) {
        if (!at.empty()) at += '.';
        at += printable(key_, non_ascii_bytes::keep);
    } else {
        at += fmt::format("[{}]", index_);
        if (!label_.empty()) at += fmt::format(" ({})", label_);
    }
    return at;
}

void json_io::fail(const std::string& problem) const { throw input_error(file_ ? *file_ : "", line_, path(), problem); }

void json_io::fail(std::string_view key, const std::string& problem) const {
    std::string at = path();
    if (!key.empty() && !at.empty() && key.front() != ' ' && key.front() != '[') at += '.';
    throw input_error(file_ ? *file_ : "", line_, at + std::string(key), problem);
}

std::string json_io::shown(const json& j) {
    std::string text = j.dump();
    return text.size() > 60 ? text.substr(0, 60) + "…" : text;
}

std::string json_io::quoted(std::string_view text) { return "'" + printable(text) + "'"; }

bool json_io::has(const char* key) const {
    if (!reading()) return false;
    if (!in_->is_object()) fail("is not a JSON object");
    return in_->contains(key);
}

const json& json_io::member(const char* key) const {
    if (!in_->is_object()) fail("is not a JSON object");
    const auto it = in_->find(key);
    if (it == in_->end()) fail(key, "is missing");
    return *it;
}

void json_io::sized(std::size_t n) const {
    if (!reading()) {
        *out_ = json::array();
        return;
    }
    if (!in_->is_array()) fail("is " + shown(*in_) + ", expected an array");
    if (in_->size() != n) fail(fmt::format("has {} entries, expected {}", in_->size(), n));
}

void json_io::scalar(std::size_t& v) {
    if (!reading()) {
        *out_ = v;
    } else {
        if (!in_->is_number_unsigned()) fail("is " + shown(*in_) + ", expected a whole number ≥ 0");
        v = in_->get<std::size_t>();
    }
}

void json_io::scalar(std::string& v) {
    if (!reading()) {
        *out_ = v;
    } else {
        if (!in_->is_string()) fail("is " + shown(*in_) + ", expected a string");
        v = in_->get_ref<const std::string&>();
    }
}

void json_io::scalar(bool& v) {
    if (!reading()) {
        *out_ = v;
    } else {
        if (!in_->is_boolean()) fail("is " + shown(*in_) + ", expected true or false");
        v = in_->get<bool>();
    }
}

void json_io::scalar(double& v) {
    if (!reading()) {
        *out_ = hex_float(v);
        return;
    }
    std::string text;
    scalar(text);
    try {
        v = parse_exact_double(text, file(), line_, path());
    } catch (const input_error&) {
        fail(quoted(text) + " is not a number");
    }
}

void json_io::scalar(std::optional<double>& v) {
    if (!reading()) {
        *out_ = optional_number(v);
        return;
    }
    const std::optional<std::optional<double>> read = number_from_json(*in_);
    if (!read) fail("is " + shown(*in_) + R"(, expected a number, "inf", "-inf", "nan" or null)");
    v = *read;
}

void json_io::decimal(double& v) {
    if (!reading()) {
        *out_ = v;
    } else {
        if (!in_->is_number() || !std::isfinite(in_->get<double>())) fail("is " + shown(*in_) + ", expected a number");
        v = in_->get<double>();
    }
}

void json_io::scalar(json& v) {
    if (!reading())
        *out_ = v;
    else
        v = *in_;
}

}  // namespace rayverify
