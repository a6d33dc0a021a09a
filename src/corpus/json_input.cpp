#include "corpus/json_input.h"

#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <set>
#include <vector>

#include "core/input_error.h"

namespace rayverify {

using json = nlohmann::ordered_json;

namespace {

// The DOM nlohmann builds, with the path to the value being parsed kept
// beside it (for messages) and each object's keys (to refuse a duplicate).
class checked_reader : public nlohmann::json_sax<json> {
public:
    explicit checked_reader(json& document) : dom_(document, false) {}

    bool null() override { return value(), dom_.null(); }
    bool boolean(bool v) override { return value(), dom_.boolean(v); }
    bool number_integer(number_integer_t v) override { return value(), dom_.number_integer(v); }
    bool number_unsigned(number_unsigned_t v) override { return value(), dom_.number_unsigned(v); }
    bool number_float(number_float_t v, const string_t& text) override { return value(), dom_.number_float(v, text); }
    bool string(string_t& v) override { return value(), dom_.string(v); }
    bool binary(binary_t& v) override { return value(), dom_.binary(v); }
    bool start_object(std::size_t n) override {
        value();
        frames_.push_back({true, {}, 0, {}});
        return dom_.start_object(n);
    }
    bool key(string_t& k) override {
        frame& f = frames_.back();
        f.key = k;
        if (!f.keys.insert(k).second) {
            problem_ = "the key \"" + k + "\" is given twice in one object";
            return false;
        }
        return dom_.key(k);
    }
    bool end_object() override {
        frames_.pop_back();
        return dom_.end_object();
    }
    bool start_array(std::size_t n) override {
        value();
        frames_.push_back({false, {}, 0, {}});
        return dom_.start_array(n);
    }
    bool end_array() override {
        frames_.pop_back();
        return dom_.end_array();
    }
    bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception& e) override {
        value();  // the value that failed is where the error is
        position_ = position;
        problem_ = e.what();
        // "[json.exception.out_of_range.406] number overflow ...": the library's prefix says nothing to a user.
        if (const std::size_t end = problem_.find("] "); problem_.starts_with("[json.exception.") && end != std::string::npos)
            problem_.erase(0, end + 2);
        return false;
    }

    // Where the value being read sits: "t0", "hit_point[1]", "" for the document.
    std::string field() const {
        std::string path;
        for (const frame& f : frames_) {
            if (f.object && !f.key.empty())
                path += (path.empty() ? "" : ".") + f.key;
            else if (!f.object && f.index > 0)
                path += fmt::format("[{}]", f.index - 1);
        }
        return path;
    }
    const std::string& problem() const { return problem_; }
    std::optional<std::size_t> position() const { return position_; }

private:
    struct frame {
        bool object;
        std::string key;        // the key whose value is being read
        std::size_t index = 0;  // in an array: the values begun so far
        std::set<std::string> keys;
    };
    void value() {
        if (!frames_.empty() && !frames_.back().object) ++frames_.back().index;
    }

    nlohmann::detail::json_sax_dom_parser<json> dom_;
    std::vector<frame> frames_;
    std::string problem_;
    std::optional<std::size_t> position_;
};

}  // namespace

json parse_json_input(std::string_view text, const std::string& file, std::size_t first_line) {
    json document;
    checked_reader reader(document);
    bool parsed = false;
    try {
        parsed = json::sax_parse(text.begin(), text.end(), &reader);
    } catch (const json::exception& e) {
        throw input_error(file, first_line, reader.field(), fmt::format("not JSON: {}", e.what()));
    }
    if (parsed) return document;
    // The line the problem is on: the document's first, plus the line breaks before it.
    std::size_t line = first_line;
    if (const auto at = reader.position())
        line += static_cast<std::size_t>(
            std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(std::min(*at, text.size())), '\n'));
    throw input_error(file, line, reader.field(), reader.problem().empty() ? "not JSON" : reader.problem());
}

}  // namespace rayverify
