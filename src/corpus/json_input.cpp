#include "corpus/json_input.h"

#include <fmt/format.h>

#include <algorithm>
#include <iterator>
#include <optional>
#include <set>
#include <vector>

#include "core/input_error.h"

namespace rayverify {

using json = nlohmann::ordered_json;

namespace {

// The text as the parser reads it, one character at a time, keeping how far
// it has read (`read`, shared by the copies the parser makes): the byte a
// value ends on, for its line.
class counting_iterator {
public:
    using iterator_category = std::input_iterator_tag;
    using value_type = char;
    using difference_type = std::ptrdiff_t;
    using pointer = const char*;
    using reference = const char&;

    counting_iterator(const char* at, const char** read) : at_(at), read_(read) {}
    reference operator*() const { return *at_; }
    counting_iterator& operator++() {
        *read_ = ++at_;
        return *this;
    }
    counting_iterator operator++(int) {
        counting_iterator before = *this;
        ++*this;
        return before;
    }
    bool operator==(const counting_iterator& other) const { return at_ == other.at_; }
    bool operator!=(const counting_iterator& other) const { return at_ != other.at_; }

private:
    const char* at_;
    const char** read_;
};

// The DOM nlohmann builds, with the path to the value being parsed kept
// beside it (for messages), each object's keys (to refuse a duplicate), the
// depth (refused beyond json_input_max_depth) and, when asked, each value's line.
class checked_reader : public nlohmann::json_sax<json> {
public:
    // `lines`: where each value's line goes (nullptr: not recorded); `text`
    // and `read`: the text and how far the parser has read it.
    checked_reader(json& document, std::map<std::string, std::size_t>* lines = nullptr, std::string_view text = {},
                   const char* const* read = nullptr, std::size_t first_line = 1)
        : dom_(document, false), lines_(lines), text_(text), read_(read), line_(first_line) {}

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
        return deep_enough() && dom_.start_object(n);
    }
    bool key(string_t& k) override {
        frame& f = frames_.back();
        f.key = k;
        if (!f.keys.insert(k).second) {
            if (read_ != nullptr) position_ = static_cast<std::size_t>(*read_ - text_.data());
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
        return deep_enough() && dom_.start_array(n);
    }
    bool end_array() override {
        frames_.pop_back();
        return dom_.end_array();
    }
    bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception& e) override {
        value();  // the value that failed is where the error is
        position_ = position;
        // "[json.exception.parse_error.101] parse error at line 1, column 2: syntax error ...": the line is
        // the message's own, and the library's prefix says nothing to a user.
        std::string what = e.what();
        if (const std::size_t at = what.find("syntax error"); at != std::string::npos)
            what = "not valid JSON: " + what.substr(at);
        else if (const std::size_t end = what.find("] "); what.starts_with("[json.exception.") && end != std::string::npos)
            what.erase(0, end + 2);
        problem_ = printable(what);
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
    bool too_deep() const { return too_deep_; }
    std::optional<std::size_t> position() const { return position_; }

private:
    struct frame {
        bool object;
        std::string key;        // the key whose value is being read
        std::size_t index = 0;  // in an array: the values begun so far
        std::set<std::string> keys;
    };
    // A value begins: counted in its array, and its line recorded (the parser
    // has read it up to its last character, or one beyond for a number: a
    // value never spans lines).
    void value() {
        if (!frames_.empty() && !frames_.back().object) ++frames_.back().index;
        if (lines_ == nullptr) return;
        const std::size_t end = static_cast<std::size_t>(*read_ - text_.data());
        if (end > counted_ + 1) {
            line_ += static_cast<std::size_t>(std::count(text_.begin() + static_cast<std::ptrdiff_t>(counted_),
                                                         text_.begin() + static_cast<std::ptrdiff_t>(end - 1), '\n'));
            counted_ = end - 1;
        }
        lines_->emplace(field(), line_);
    }
    bool deep_enough() {
        if (frames_.size() <= json_input_max_depth) return true;
        too_deep_ = true;
        problem_ = fmt::format("nested more than {} levels deep", json_input_max_depth);
        if (read_ != nullptr) position_ = static_cast<std::size_t>(*read_ - text_.data());
        return false;
    }

    nlohmann::detail::json_sax_dom_parser<json> dom_;
    std::vector<frame> frames_;
    std::string problem_;
    std::optional<std::size_t> position_;
    bool too_deep_ = false;
    std::map<std::string, std::size_t>* lines_;
    std::string_view text_;
    const char* const* read_;
    std::size_t line_;          // of the byte counted_
    std::size_t counted_ = 0;   // the bytes before it are counted in line_
};

}  // namespace

namespace {

// Parses `text` into `document` through `reader`, from `first`; throws
// input_error at the line and field of the first problem.
template <class Iterator>
void parse_checked(Iterator first, Iterator last, checked_reader& reader, std::string_view text,
                   const std::string& file, std::size_t first_line) {
    bool parsed = false;
    try {
        parsed = json::sax_parse(first, last, &reader);
    } catch (const json::exception& e) {
        throw input_error(file, first_line, reader.field(), fmt::format("not JSON: {}", e.what()));
    }
    if (parsed) return;
    // The line the problem is on: the document's first, plus the line breaks before it.
    std::size_t line = first_line;
    if (const auto at = reader.position())
        line += static_cast<std::size_t>(
            std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(std::min(*at, text.size())), '\n'));
    // A path a thousand levels deep says nothing: the depth is the problem.
    throw input_error(file, line, reader.too_deep() ? "" : reader.field(),
                      reader.problem().empty() ? "not JSON" : reader.problem());
}

}  // namespace

json parse_json_input(std::string_view text, const std::string& file, std::size_t first_line) {
    json document;
    checked_reader reader(document);
    parse_checked(text.begin(), text.end(), reader, text, file, first_line);
    return document;
}

located_json parse_located_json_input(std::string_view text, const std::string& file, std::size_t first_line) {
    located_json located;
    const char* read = text.data();
    checked_reader reader(located.document, &located.lines, text, &read, first_line);
    parse_checked(counting_iterator(text.data(), &read), counting_iterator(text.data() + text.size(), &read), reader,
                  text, file, first_line);
    return located;
}

std::size_t located_json::line_of(std::string path) const {
    while (true) {
        if (const auto it = lines.find(path); it != lines.end()) return it->second;
        if (path.empty()) return 0;
        const std::size_t cut = path.find_last_of(".[");
        path = cut == std::string::npos ? std::string() : path.substr(0, cut);
    }
}

}  // namespace rayverify
