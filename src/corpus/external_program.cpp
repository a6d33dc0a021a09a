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

#include "core/process_status.h"
#include "corpus/case_stream.h"

namespace rayverify {

namespace {

using steady = std::chrono::steady_clock;

// Where a complete answer to `cases` cases ends in `text`, or npos: the header
// line, then (CSV) the column row, then one line per case; blank lines (and
// CSV comment lines) are not counted.
std::size_t answer_end(std::string_view text, exchange_format format, std::size_t cases) {
    const std::size_t needed = cases + (format == exchange_format::csv ? 2 : 1);
    std::size_t counted = 0;
    for (std::size_t at = 0;;) {
        const std::size_t end = text.find('\n', at);
        if (end == std::string_view::npos) return std::string_view::npos;
        std::string_view line = text.substr(at, end - at);
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        const bool blank = line.find_first_not_of(" \t") == std::string_view::npos;
        const bool comment = format == exchange_format::csv && counted > 0 && !blank && line.front() == '#';
        if (!blank && !comment) ++counted;
        at = end + 1;
        if (counted == needed) return at;
    }
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
        ::execl("/bin/sh", "sh", "-c", command_.c_str(), static_cast<char*>(nullptr));
        ::_exit(127);
    }
    ::close(in[0]);
    ::close(out[1]);
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
    kill_session();  // anything it started and left running
    pid_ = -1;
    return status ? describe_wait_status(*status) : "ended";
}

void external_program::kill_session() {
    if (pid_ <= 0) return;
    ::kill(-pid_, SIGKILL);  // its process group, the session's first
    // A process that moved to a group of its own is still in the session:
    // /proc/PID/stat's sixth field is the session id.
    std::error_code error;
    for (const auto& entry : std::filesystem::directory_iterator("/proc", error)) {
        const std::string name = entry.path().filename().string();
        if (name.empty() || name.find_first_not_of("0123456789") != std::string::npos) continue;
        std::ifstream stat(entry.path() / "stat");
        std::string text;
        if (!std::getline(stat, text)) continue;
        const std::size_t after_name = text.rfind(')');  // the command name may hold spaces
        if (after_name == std::string::npos) continue;
        std::istringstream fields(text.substr(after_name + 1));
        std::string state;
        long long parent = 0, group = 0, session = 0;
        if (!(fields >> state >> parent >> group >> session)) continue;
        if (session == pid_) ::kill(static_cast<pid_t>(std::stoll(name)), SIGKILL);
    }
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
                       {prec_, exchange_fingerprint(input_fingerprint, prec_), cases.size(), number_style::decimal});
    for (const corpus_case& c : cases) writer.write(c);
    writer.finish();
    const std::string bytes = request.str();

    // Write the batch and read the answer together: a program may answer
    // case by case while it reads, and neither pipe may fill up and block it.
    const steady::time_point deadline = deadline_after(timeout_seconds_);
    std::size_t written = 0;
    std::string reply = std::move(pending_);
    pending_.clear();
    std::size_t end = answer_end(reply, format_, cases.size());
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
            end = answer_end(reply, format_, cases.size());
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
