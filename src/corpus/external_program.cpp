#include "corpus/external_program.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <poll.h>
#include <sys/prctl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <climits>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "core/child_processes.h"
#include "core/process_status.h"
#include "corpus/case_stream.h"

namespace rayverify {

namespace {

using steady = std::chrono::steady_clock;

// The answer to one batch as it arrives, line by line: each byte is looked
// at once (never rescanned from the start), the first line is checked as a
// results header the moment it is complete, and the answer may not grow past
// what a batch of its size can need.
class answer_reader {
public:
    answer_reader(std::string name, exchange_format format, std::span<const corpus_case> cases)
        : name_(std::move(name)), format_(format), needed_(cases.size() + (format == exchange_format::csv ? 2 : 1)) {
        // A results line is an id and at most 15 numbers: 4 KiB beyond its id is room to spare.
        limit_ = 65536;
        for (const corpus_case& c : cases) limit_ += 4096 + c.id.size();
    }

    // Takes the bytes read so far (`text`, grown since the last call); the
    // end of the complete answer in it, or npos. Throws input_error for a
    // first line that is no results header, a line over 1 MiB, or an answer
    // longer than the limit.
    std::size_t scan(std::string_view text) {
        for (;;) {
            const std::size_t end = text.find('\n', scanned_);
            if (end == std::string_view::npos) {
                scanned_ = text.size();
                if (text.size() - line_start_ > max_answer_line)
                    throw input_error(name_, lines_ + 1, "", "a line longer than 1 MiB");
                if (text.size() > limit_)
                    throw input_error(name_, 0, "",
                                      fmt::format("{} bytes without completing the answer, more than a batch of {} "
                                                  "cases can need ({} bytes)",
                                                  text.size(), needed_ - 1 - (format_ == exchange_format::csv),
                                                  limit_));
                return std::string_view::npos;
            }
            std::string_view line = text.substr(line_start_, end - line_start_);
            scanned_ = line_start_ = end + 1;
            ++lines_;
            if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
            const bool blank = line.find_first_not_of(" \t") == std::string_view::npos;
            const bool comment = format_ == exchange_format::csv && counted_ > 0 && !blank && line.front() == '#';
            if (blank || comment) continue;
            if (counted_ == 0) check_results_header(line, format_, name_, lines_);
            if (++counted_ == needed_) return line_start_;
        }
    }

private:
    static constexpr std::size_t max_answer_line = std::size_t{1} << 20;
    std::string name_;
    exchange_format format_;
    std::size_t needed_;
    std::size_t limit_ = 0;
    std::size_t scanned_ = 0, line_start_ = 0, counted_ = 0, lines_ = 0;
};

// A command the shell runs as one program, with words, quotes and variables
// but no operator that makes it a pipeline, a list or a redirection.
bool is_simple_command(std::string_view command) {
    const std::size_t start = command.find_first_not_of(" \t");
    if (start == std::string_view::npos) return false;
    const std::string_view first_word = command.substr(start, command.find_first_of(" \t", start) - start);
    // "VAR=value program" sets a variable for the program, and a shell's own
    // builtins and keywords are no program: `exec` would look for a file of that name.
    static constexpr std::string_view shell_words[] = {
        "exit", "return", "break", "continue", ".",    ":",     "eval", "exec",   "export", "readonly",
        "set",  "shift",  "times", "trap",     "unset", "cd",   "read", "wait",   "alias",  "ulimit",
        "umask", "getopts", "local", "jobs",   "fg",    "bg",   "command", "type", "if",    "while",
        "for",  "until",  "case",  "source",   "hash"};
    return command.find_first_of(";&|<>()`\n{}!") == std::string_view::npos &&
           first_word.find('=') == std::string_view::npos &&
           std::find(std::begin(shell_words), std::end(shell_words), first_word) == std::end(shell_words);
}

}  // namespace

external_program::external_program(std::string command, exchange_format format, precision prec,
                                   double timeout_seconds)
    : command_(std::move(command)), format_(format), prec_(prec), timeout_seconds_(timeout_seconds) {
    const auto fail_start = [&](const std::string& why) { throw input_error("", 0, "--command", why); };
    if (format == exchange_format::npy)
        fail_start("a program answers over pipes in csv or jsonl (an npy needs its JSON companion): use --format");
    // A program that exits while rayverify writes to it is an error to report, not a signal that ends rayverify.
    std::signal(SIGPIPE, SIG_IGN);
    int in[2], out[2];
    if (::pipe2(in, O_CLOEXEC) != 0) fail_start(fmt::format("cannot create a pipe: {}", std::strerror(errno)));
    if (::pipe2(out, O_CLOEXEC) != 0) {
        ::close(in[0]);
        ::close(in[1]);
        fail_start(fmt::format("cannot create a pipe: {}", std::strerror(errno)));
    }
    std::fflush(nullptr);
    const pid_t parent = ::getpid();
    const pid_t pid = ::fork();
    if (pid < 0) {
        for (int fd : {in[0], in[1], out[0], out[1]}) ::close(fd);
        fail_start(fmt::format("cannot start '{}': {}", command_, std::strerror(errno)));
    }
    if (pid == 0) {
        ::prctl(PR_SET_PDEATHSIG, SIGKILL);  // killed with rayverify
        if (::getppid() != parent) ::_exit(127);
        ::setsid();  // a session of its own: what the shell starts is stopped with it
        std::signal(SIGPIPE, SIG_DFL);
        if (::dup2(in[0], STDIN_FILENO) < 0 || ::dup2(out[1], STDOUT_FILENO) < 0) ::_exit(127);
        ::close_range(3, ~0u, 0);
        // A simple command replaces the shell (exec): the program itself is
        // the session's leader, killed with rayverify (PR_SET_PDEATHSIG).
        const std::string shell_text = is_simple_command(command_) ? "exec " + command_ : command_;
        ::execl("/bin/sh", "sh", "-c", shell_text.c_str(), static_cast<char*>(nullptr));
        ::_exit(127);
    }
    ::close(in[0]);
    ::close(out[1]);
    started_child(pid);
    program_session_opened(pid);
    to_program_ = in[1];
    from_program_ = out[0];
    pid_ = pid;
    ::fcntl(to_program_, F_SETFL, ::fcntl(to_program_, F_GETFL) | O_NONBLOCK);
}

external_program::~external_program() { ended(); }

std::string external_program::ended() {
    for (int* fd : {&to_program_, &from_program_})
        if (*fd >= 0) {
            ::close(*fd);
            *fd = -1;
        }
    if (pid_ <= 0) return "ended";
    // With its input closed the program should exit; one that lingers is killed.
    const std::optional<int> status = reap_child(pid_, -pid_, std::min(timeout_seconds_, 5.0));
    child_ended(pid_);
    end_program_session(pid_);  // anything it started and left running, in its session or not
    pid_ = -1;
    return status ? describe_wait_status(*status) : "ended";
}

void external_program::kill_session() {
    if (pid_ > 0) ::kill(-pid_, SIGKILL);  // its process group; ended() takes the rest
}

void external_program::finish() {
    if (pid_ <= 0) return;
    if (to_program_ >= 0) {
        ::close(to_program_);
        to_program_ = -1;
    }
    // Its output to the end: what follows the last answer must be nothing (or blank lines).
    std::string rest = std::move(pending_);
    pending_.clear();
    const steady::time_point deadline = deadline_after(std::min(timeout_seconds_, 5.0));
    while (from_program_ >= 0 && rest.size() < (std::size_t{1} << 16)) {
        const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - steady::now()).count();
        if (left <= 0) break;
        pollfd fd{from_program_, POLLIN, 0};
        const int events = ::poll(&fd, 1, static_cast<int>(std::min<long long>(left, INT_MAX)));
        if (events < 0 && errno != EINTR) break;
        if (events <= 0) continue;
        char chunk[65536];
        const ssize_t n = ::read(from_program_, chunk, sizeof chunk);
        if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
        if (n <= 0) break;
        rest.append(chunk, static_cast<std::size_t>(n));
    }
    ended();
    const std::size_t text = rest.find_first_not_of(" \t\r\n");
    if (text == std::string::npos) return;
    std::string first = rest.substr(text, rest.find('\n', text) - text);
    if (first.size() > 80) first = first.substr(0, 77) + "...";
    for (char& c : first)
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
    throw input_error("", 0, "--command",
                      fmt::format("command '{}' wrote more after its answer to the last batch (an extra answer, or "
                                  "trailing output), beginning '{}': every batch is answered by exactly one "
                                  "results file",
                                  command_, first));
}

void external_program::fail(const std::string& happened, std::span<const corpus_case> cases) {
    const corpus_case first = cases.empty() ? corpus_case{} : cases.front();
    const std::string batch = cases.size() == 1
                                  ? fmt::format("on case {}", first.id)
                                  : fmt::format("on a batch of {} cases (the first: {})", cases.size(), first.id);
    throw case_failure("", "--command", fmt::format("command '{}' {} {}", command_, happened, batch), first);
}

std::shared_ptr<const answer_book> external_program::answer(std::span<const corpus_case> cases) {
    ++batches_;
    if (pid_ <= 0) fail("is no longer running (it failed on an earlier batch)", cases);

    case_fingerprint fingerprint;
    for (const corpus_case& c : cases) fingerprint.add(c);
    const std::string input_fingerprint = fingerprint.text();
    std::ostringstream request;
    case_writer writer(request, nullptr, format_,
                       {prec_, exchange_fingerprint(input_fingerprint, prec_), cases.size(), number_style::decimal,
                        std::ranges::any_of(cases, &corpus_case::is_segment)});
    for (const corpus_case& c : cases) writer.write(c);
    writer.finish();
    const std::string bytes = request.str();

    // Write the batch and read the answer together: a program may answer
    // case by case while it reads, and neither pipe may fill up and block it.
    const steady::time_point deadline = deadline_after(timeout_seconds_);
    std::size_t written = 0;
    std::string reply = std::move(pending_);
    pending_.clear();
    answer_reader reader(fmt::format("answer to batch {}", batches_), format_, cases);
    const auto scanned = [&] {
        try {
            return reader.scan(reply);
        } catch (const input_error& e) {
            kill_session();
            ended();
            fail(fmt::format("answered with something that is not an answer to its batch ({}); it was stopped",
                             e.what()),
                 cases);
        }
    };
    std::size_t end = scanned();
    while (end == std::string::npos) {
        const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - steady::now()).count();
        if (left <= 0) {
            kill_session();
            ended();
            fail(fmt::format("gave no answer within {:g} s (it was killed)", timeout_seconds_), cases);
        }
        pollfd fds[2] = {{from_program_, POLLIN, 0}, {to_program_, POLLOUT, 0}};
        const nfds_t count = written < bytes.size() && to_program_ >= 0 ? 2 : 1;
        const int events = ::poll(fds, count, static_cast<int>(std::min<long long>(left, INT_MAX)));
        if (events < 0 && errno != EINTR) fail(fmt::format("could not be waited for: {}", std::strerror(errno)), cases);
        if (events <= 0) continue;
        if (count == 2 && fds[1].revents != 0) {
            const ssize_t n = ::write(to_program_, bytes.data() + written, bytes.size() - written);
            if (n > 0) written += static_cast<std::size_t>(n);
            if (n < 0 && errno != EAGAIN && errno != EINTR) {
                // It closed its input (or exited): what it wrote, and how it ended, tell which.
                ::close(to_program_);
                to_program_ = -1;
            }
        }
        if (fds[0].revents != 0) {
            char chunk[65536];
            const ssize_t n = ::read(from_program_, chunk, sizeof chunk);
            if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
            if (n <= 0) fail(ended(), cases);  // end of its output: it exited or closed it
            reply.append(chunk, static_cast<std::size_t>(n));
            end = scanned();
        }
    }
    pending_ = reply.substr(end);
    reply.resize(end);

    // The answer must be a results file for exactly these cases.
    try {
        results_scope scope;
        for (const corpus_case& c : cases) scope.add(c.id);
        scope.input_fingerprint = input_fingerprint;
        results_file results =
            parse_results(fmt::format("answer to batch {}", batches_), reply, format_, std::nullopt, &scope);
        answer_matcher matcher(results);
        for (const corpus_case& c : cases) matcher.add(c);
        return matcher.finish(input_fingerprint);
    } catch (const input_error& e) {
        kill_session();
        ended();
        fail(fmt::format("answered with something that is not an answer to its batch ({}); it was stopped", e.what()),
             cases);
    }
}

}  // namespace rayverify
