#include "core/outputs.h"

#include <dirent.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <mutex>
#include <optional>
#include <random>
#include <sstream>
#include <streambuf>
#include <utility>

#include "core/child_processes.h"
#include "core/input_error.h"

namespace rayverify {

namespace fs = std::filesystem;

namespace {

// ---- The cleanup registry: what a signal or exit hook removes ----
//
// Fixed slots of plain characters, so that a signal handler can read them
// without allocating or locking. A slot is claimed (free → busy), filled,
// then published with its kind; the handler only reads published slots.

enum slot_kind : int { free_slot = 0, busy_slot, temporary_file, staging_dir, lock_file, created_dir };

struct slot {
    std::atomic<int> kind{free_slot};
    char path[PATH_MAX];
};

constexpr int slot_count = 256;
slot slots[slot_count];
std::atomic<pid_t> registry_owner{0};  // the process whose outputs these are (not a forked child)
std::atomic<bool> command_in_progress{false};

int enlist(slot_kind kind, const fs::path& path) {
    const std::string& text = path.native();
    if (text.size() >= PATH_MAX) throw input_error(text, 0, "", "the path is too long");
    registry_owner.store(::getpid());
    for (int i = 0; i < slot_count; ++i) {
        int expected = free_slot;
        if (!slots[i].kind.compare_exchange_strong(expected, busy_slot)) continue;
        std::memcpy(slots[i].path, text.c_str(), text.size() + 1);
        slots[i].kind.store(kind, std::memory_order_release);
        return i;
    }
    throw std::runtime_error("more than 256 unfinished outputs at once");
}

void release(int& index) {
    if (index >= 0) slots[index].kind.store(free_slot, std::memory_order_release);
    index = -1;
}

// Everything in a directory (one level: a staging directory holds files only), then the directory.
void remove_directory_now(const char* path) noexcept {
    const int dir = ::open(path, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (dir >= 0) {
        alignas(8) char entries[4096];
        for (;;) {
            const long n = ::syscall(SYS_getdents64, dir, entries, sizeof entries);
            if (n <= 0) break;
            for (long at = 0; at < n;) {
                const auto* e = reinterpret_cast<const struct dirent64*>(entries + at);
                at += e->d_reclen;
                const char* name = e->d_name;
                if (std::strcmp(name, ".") != 0 && std::strcmp(name, "..") != 0) ::unlinkat(dir, name, 0);
            }
        }
        ::close(dir);
    }
    ::rmdir(path);
}

const int cleanup_signals[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT};
struct sigaction previous_actions[std::size(cleanup_signals)];

void on_cleanup_signal(int signal) {
    const int saved_errno = errno;
    end_program_sessions_now();  // the programs and engines running, and all they started
    remove_unfinished_outputs();
    // The signal's own action (the default: end the process) as soon as this handler returns.
    for (std::size_t i = 0; i < std::size(cleanup_signals); ++i)
        if (cleanup_signals[i] == signal) ::sigaction(signal, &previous_actions[i], nullptr);
    ::raise(signal);
    errno = saved_errno;
}

void install_signal_handlers() {
    static std::once_flag once;
    std::call_once(once, [] {
        struct sigaction action {};
        action.sa_handler = on_cleanup_signal;
        sigemptyset(&action.sa_mask);
        for (int s : cleanup_signals) sigaddset(&action.sa_mask, s);
        for (std::size_t i = 0; i < std::size(cleanup_signals); ++i) {
            ::sigaction(cleanup_signals[i], nullptr, &previous_actions[i]);
            // A signal the caller ignores (nohup, a background job) stays ignored.
            if (previous_actions[i].sa_handler == SIG_IGN) continue;
            ::sigaction(cleanup_signals[i], &action, nullptr);
        }
        // A reader that closes a pipe (`rayverify audit --report d | head`)
        // makes the write fail with EPIPE instead of ending the process: what
        // remains of standard output is dropped, the files are still written
        // (guard_standard_output). A handler, not SIG_IGN, so that the
        // programs rayverify starts get the default action back at exec.
        struct sigaction pipe_action {};
        pipe_action.sa_handler = [](int) {};
        pipe_action.sa_flags = SA_RESTART;
        sigemptyset(&pipe_action.sa_mask);
        struct sigaction caller_pipe_action {};
        ::sigaction(SIGPIPE, nullptr, &caller_pipe_action);
        if (caller_pipe_action.sa_handler != SIG_IGN) ::sigaction(SIGPIPE, &pipe_action, nullptr);
        // Past RLIMIT_FSIZE a write fails with EFBIG (an error we report and
        // clean up after) instead of the default SIGXFSZ ending the process.
        ::signal(SIGXFSZ, SIG_IGN);
    });
}

// Holds the cleanup signals in this thread while the renames of a commit run.
class signals_held {
public:
    signals_held() {
        sigset_t set;
        sigemptyset(&set);
        for (int s : cleanup_signals) sigaddset(&set, s);
        ::pthread_sigmask(SIG_BLOCK, &set, &previous_);
    }
    ~signals_held() { ::pthread_sigmask(SIG_SETMASK, &previous_, nullptr); }
    signals_held(const signals_held&) = delete;
    signals_held& operator=(const signals_held&) = delete;

private:
    sigset_t previous_;
};

std::string error_text(int error) { return std::strerror(error); }

mode_t creation_mode() {
    static const mode_t mode = [] {
        const mode_t mask = ::umask(0);
        ::umask(mask);
        return static_cast<mode_t>(0666 & ~mask);
    }();
    return mode;
}

// A unique name beside `target`: ".NAME.rayverify-<tag>-XXXXXX" (hidden, and
// never ending in .txt or .csv, so that no corpus listing picks it up).
std::string hidden_name(const fs::path& target, const char* tag) {
    return "." + target.filename().string() + ".rayverify-" + tag + "-";
}

std::string random_suffix() {
    static std::mt19937_64 random(std::random_device{}() ^ static_cast<std::uint64_t>(::getpid()));
    static const char letters[] = "abcdefghijklmnopqrstuvwxyz0123456789";
    std::string s;
    for (int i = 0; i < 8; ++i) s += letters[random() % (sizeof letters - 1)];
    return s;
}

void sync_directory(const fs::path& dir) {
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;
    ::fsync(fd);
    ::close(fd);
}

// An existing file's identity.
struct file_id {
    dev_t device = 0;
    ino_t inode = 0;
    bool operator==(const file_id&) const = default;
};

std::optional<file_id> id_of(const fs::path& path) {
    struct stat s {};
    if (::stat(path.c_str(), &s) != 0) return std::nullopt;
    return file_id{s.st_dev, s.st_ino};
}

fs::path resolved(const fs::path& path) {
    std::error_code error;
    fs::path out = fs::weakly_canonical(fs::absolute(path, error), error);
    return error ? fs::absolute(path).lexically_normal() : out;
}

bool is_corpus_name(const fs::path& path) {
    std::string ext = path.extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext == ".txt" || ext == ".csv";
}

std::string host_name() {
    char name[256] = {};
    if (::gethostname(name, sizeof name - 1) != 0) return "?";
    return name;
}

std::string process_command_line() {
    std::ifstream in("/proc/self/cmdline", std::ios::binary);
    std::string raw((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    for (char& c : raw)
        if (c == '\0' || c == '\n') c = ' ';
    while (!raw.empty() && raw.back() == ' ') raw.pop_back();
    return raw;
}

std::string utc_now() {
    const std::time_t now = std::time(nullptr);
    std::tm parts{};
    ::gmtime_r(&now, &parts);
    char text[32];
    std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &parts);
    return text;
}

constexpr const char* lock_name = ".rayverify-lock";

// "key value" lines of a lock file.
std::string lock_field(const std::string& text, const std::string& key) {
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);)
        if (line.starts_with(key + " ")) return line.substr(key.size() + 1);
    return "";
}

}  // namespace

// ---- output_file ----

// Buffered writes to a descriptor; a failed write throws input_error naming the output.
struct output_file::buffer : std::streambuf {
    buffer(int fd, const output_file& owner) : fd(fd), owner(owner) { setp(data.data(), data.data() + data.size()); }

    void drain() {
        write_all(pbase(), static_cast<std::size_t>(pptr() - pbase()));
        setp(data.data(), data.data() + data.size());
    }

    void write_all(const char* p, std::size_t size) {
        while (size > 0) {
            const ssize_t n = ::write(fd, p, size);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) {
                const int error = n < 0 ? errno : EIO;
                setp(data.data(), data.data() + data.size());
                throw input_error(owner.path_.string(), 0, owner.option_, "cannot write: " + error_text(error));
            }
            p += n;
            size -= static_cast<std::size_t>(n);
        }
    }

    int_type overflow(int_type c) override {
        drain();
        if (!traits_type::eq_int_type(c, traits_type::eof())) {
            *pptr() = traits_type::to_char_type(c);
            pbump(1);
        }
        return traits_type::not_eof(c);
    }

    std::streamsize xsputn(const char* s, std::streamsize n) override {
        if (n <= epptr() - pptr()) {
            std::memcpy(pptr(), s, static_cast<std::size_t>(n));
            pbump(static_cast<int>(n));
            return n;
        }
        drain();
        write_all(s, static_cast<std::size_t>(n));
        return n;
    }

    int sync() override {
        drain();
        return 0;
    }

    int fd;
    const output_file& owner;
    std::array<char, 1 << 16> data{};
};

output_file::output_file(fs::path path, std::string option) : path_(std::move(path)), option_(std::move(option)) {}

output_file::~output_file() {
    stream_.reset();
    buffer_.reset();
    if (fd_ >= 0) ::close(fd_);
    if (slot_ >= 0) {
        ::unlink(temporary_.c_str());
        release(slot_);
    }
}

std::ostream& output_file::stream() { return *stream_; }

// ---- run_outputs ----

struct run_outputs::entry {
    fs::path path, canonical;
    std::string option;
    std::optional<file_id> id;
    bool corpus_directory = false;
};

struct run_outputs::owned_directory {
    fs::path path;
    std::vector<std::pair<fs::path, int>> created;  // directories made by this run (outermost first), slots
    fs::path lock;
    int lock_slot = -1;
    std::vector<std::pair<fs::path, int>> staging;
};

run_outputs::run_outputs() {
    install_signal_handlers();
    creation_mode();
}

run_outputs::~run_outputs() {
    files_.clear();  // removes the temporaries
    for (auto& d : directories_) {
        for (auto& [path, slot] : d->staging) {
            std::error_code ignored;
            if (!committed_) fs::remove_all(path, ignored);
            release(slot);
        }
        if (d->lock_slot >= 0) {
            ::unlink(d->lock.c_str());
            release(d->lock_slot);
        }
    }
    for (auto d = directories_.rbegin(); d != directories_.rend(); ++d)
        for (auto c = (*d)->created.rbegin(); c != (*d)->created.rend(); ++c) {
            if (!committed_) ::rmdir(c->first.c_str());  // only when empty
            release(c->second);
        }
}

void run_outputs::input(const fs::path& path, const std::string& option, bool corpus_directory) {
    auto e = std::make_unique<entry>();
    e->path = path;
    e->canonical = resolved(path);
    e->option = option;
    e->id = id_of(path);
    e->corpus_directory = corpus_directory;
    inputs_.push_back(std::move(e));
}

void run_outputs::check_against_inputs(const fs::path& path, const std::string& option, bool directory) const {
    const std::optional<file_id> id = id_of(path);
    const fs::path canonical = resolved(path);
    for (const auto& in : inputs_) {
        const bool same = (id && in->id && *id == *in->id) || canonical == in->canonical;
        const std::string input = in->path.string() + " (" + in->option + ")";
        if (same && in->corpus_directory)
            throw input_error(path.string(), 0, option,
                              "is the corpus directory " + input +
                                  ": outputs there would be read as corpus files by the next audit; choose "
                                  "another directory");
        if (same)
            throw input_error(path.string(), 0, option,
                              std::string("is the same ") + (directory ? "directory" : "file") + " as the input " +
                                  input + ": writing it would destroy that input");
        if (!directory && in->corpus_directory && is_corpus_name(path)) {
            const std::optional<file_id> parent = id_of(canonical.parent_path());
            if ((parent && in->id && *parent == *in->id) || canonical.parent_path() == in->canonical)
                throw input_error(path.string(), 0, option,
                                  "lies in the corpus directory " + input +
                                      ", where the next audit would read it as a corpus file");
        }
    }
}

void run_outputs::directory(const fs::path& dir, const std::string& option) {
    for (const auto& d : directories_)
        if (resolved(d->path) == resolved(dir)) return;  // declared already (by this run)
    check_against_inputs(dir, option, true);
    auto owned = std::make_unique<owned_directory>();
    owned->path = dir;
    // Create the missing components, outermost first, remembering each.
    std::error_code error;
    const fs::path absolute = fs::absolute(dir, error).lexically_normal();
    fs::path prefix;
    for (const fs::path& part : absolute) {
        prefix /= part;
        if (part.empty() || prefix == prefix.root_path()) continue;
        struct stat s {};
        if (::stat(prefix.c_str(), &s) == 0) {
            if (!S_ISDIR(s.st_mode))
                throw input_error(dir.string(), 0, option,
                                  "cannot create directory: '" + (prefix == absolute ? dir : prefix).string() +
                                      "' exists and is not a directory");
            continue;
        }
        if (::mkdir(prefix.c_str(), 0777) != 0 && errno != EEXIST)
            throw input_error(dir.string(), 0, option, "cannot create directory: " + error_text(errno));
        owned->created.emplace_back(prefix, enlist(created_dir, prefix));
    }
    // The lock: a file created exclusively, naming this run; a lock whose run is gone is taken over.
    owned->lock = absolute / lock_name;
    for (int attempt = 0;; ++attempt) {
        const int fd = ::open(owned->lock.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
        if (fd >= 0) {
            owned->lock_slot = enlist(lock_file, owned->lock);
            const std::string text = "rayverify run in progress\npid " + std::to_string(::getpid()) + "\nhost " +
                                     host_name() + "\nstarted " + utc_now() + "\ncommand " +
                                     process_command_line() + "\n";
            const ssize_t written = ::write(fd, text.data(), text.size());
            const int e = written < 0 ? errno : ENOSPC;
            ::close(fd);
            if (written != static_cast<ssize_t>(text.size())) {
                directories_.push_back(std::move(owned));  // removed with the rest
                throw input_error(dir.string(), 0, option,
                                  "cannot write its lock file " + std::string(lock_name) + ": " + error_text(e));
            }
            break;
        }
        if (errno != EEXIST) {
            const int e = errno;
            directories_.push_back(std::move(owned));
            throw input_error(dir.string(), 0, option, "cannot create its lock file " + std::string(lock_name) +
                                                           ": " + error_text(e));
        }
        std::ifstream in(owned->lock, std::ios::binary);
        const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        const std::string pid = lock_field(text, "pid"), host = lock_field(text, "host");
        // On this host, a lock whose process no longer exists is stale: the run was killed.
        const long other = std::atol(pid.c_str());
        if (attempt == 0 && host == host_name() && other > 0 && ::kill(static_cast<pid_t>(other), 0) != 0 &&
            errno == ESRCH) {
            ::unlink(owned->lock.c_str());
            continue;
        }
        directories_.push_back(std::move(owned));
        throw input_error(dir.string(), 0, option,
                          "is in use by another rayverify run (pid " + (pid.empty() ? "?" : pid) + " on " +
                              (host.empty() ? "?" : host) + ", started " + lock_field(text, "started") + ": " +
                              lock_field(text, "command") + "); wait for it to finish, or remove " +
                              (dir / lock_name).string() + " if that run is gone");
    }
    directories_.push_back(std::move(owned));
}

output_file& run_outputs::file(const fs::path& path, const std::string& option) {
    auto out = std::make_unique<output_file>(path, option);
    const auto fail = [&](const std::string& problem) { return input_error(path.string(), 0, option, problem); };
    struct stat link {}, target {};
    const bool exists = ::lstat(path.c_str(), &link) == 0;
    const bool resolves = exists && ::stat(path.c_str(), &target) == 0;
    if (exists && !resolves) throw fail("is a symbolic link to a missing file");
    if (resolves && S_ISDIR(target.st_mode)) throw fail("is a directory, expected a file to write");

    if (resolves && !S_ISREG(target.st_mode)) {
        // A device, pipe, socket or terminal: written through, never replaced.
        out->fd_ = ::open(path.c_str(), O_WRONLY | O_CLOEXEC | O_NOCTTY);
        if (out->fd_ < 0) throw fail("cannot open for writing: " + error_text(errno));
        out->written_through_ = true;
    } else {
        out->target_ = S_ISLNK(link.st_mode) ? fs::canonical(path) : resolved(path);
        struct stat standard_output {};
        if (resolves && ::fstat(STDOUT_FILENO, &standard_output) == 0 && S_ISREG(standard_output.st_mode) &&
            standard_output.st_dev == target.st_dev && standard_output.st_ino == target.st_ino)
            throw fail("is where standard output goes: give this output a file of its own");
        check_against_inputs(path, option, false);
        for (const fs::path& other : declared_)
            if (other == out->target_) throw fail("is named by another output of this command too");
        const fs::path dir = out->target_.parent_path();
        std::string name = (dir / hidden_name(out->target_, "new")).string() + "XXXXXX";
        out->fd_ = ::mkostemp(name.data(), O_CLOEXEC);
        if (out->fd_ < 0) {
            // The directory as the user named it, unless a link led elsewhere.
            const fs::path named = S_ISLNK(link.st_mode) ? dir : path.parent_path().empty() ? "." : path.parent_path();
            throw fail("cannot write into directory '" + named.string() + "': " + error_text(errno));
        }
        out->temporary_ = name;
        out->slot_ = enlist(temporary_file, out->temporary_);
        ::fchmod(out->fd_, resolves ? (target.st_mode & 07777) : creation_mode());
        declared_.push_back(out->target_);
    }
    out->buffer_ = std::make_unique<output_file::buffer>(out->fd_, *out);
    out->stream_ = std::make_unique<std::ostream>(out->buffer_.get());
    out->stream_->exceptions(std::ios::badbit);
    files_.push_back(std::move(out));
    return *files_.back();
}

fs::path run_outputs::staging_directory(const fs::path& dir) {
    for (auto& d : directories_) {
        if (d->path != dir) continue;
        std::string name = (fs::absolute(dir) / ".rayverify-stage-").string() + "XXXXXX";
        if (!::mkdtemp(name.data()))
            throw input_error(dir.string(), 0, "", "cannot create a staging directory: " + error_text(errno));
        d->staging.emplace_back(name, enlist(staging_dir, name));
        return name;
    }
    throw std::logic_error("staging_directory: " + dir.string() + " was not declared with directory()");
}

void run_outputs::adopt(const fs::path& staged, const fs::path& target) {
    const fs::path canonical = resolved(target);
    check_against_inputs(target, "", false);
    for (const fs::path& other : declared_)
        if (other == canonical) throw input_error(target.string(), 0, "", "is named by another output of this command too");
    declared_.push_back(canonical);
    adopted_.emplace_back(staged, canonical);
}

void run_outputs::commit() {
    // Every byte written and on disk before any file is put in place.
    for (auto& f : files_) {
        f->stream_->flush();
        if (f->written_through_) continue;
        if (::fsync(f->fd_) != 0)
            throw input_error(f->path_.string(), 0, f->option_, "cannot write: " + error_text(errno));
        const int fd = std::exchange(f->fd_, -1);
        if (::close(fd) != 0) throw input_error(f->path_.string(), 0, f->option_, "cannot write: " + error_text(errno));
    }
    for (const auto& [staged, target] : adopted_) {
        const int fd = ::open(staged.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd < 0 || ::fsync(fd) != 0) {
            const int e = errno;
            if (fd >= 0) ::close(fd);
            throw input_error(target.string(), 0, "", "cannot write: " + error_text(e));
        }
        ::close(fd);
    }

    // The renames, with the signals held: an interrupted commit would leave some files in place.
    const signals_held held;
    struct placed {
        fs::path target, backup;  // backup: a hard link to the file it replaced, empty when none
    };
    std::vector<placed> done;
    const auto roll_back = [&] {
        for (auto p = done.rbegin(); p != done.rend(); ++p) {
            if (p->backup.empty())
                ::unlink(p->target.c_str());
            else
                ::rename(p->backup.c_str(), p->target.c_str());
        }
    };
    std::vector<std::pair<fs::path, fs::path>> moves;  // from → to
    for (auto& f : files_)
        if (!f->written_through_) moves.emplace_back(f->temporary_, f->target_);
    moves.insert(moves.end(), adopted_.begin(), adopted_.end());
    for (const auto& [from, to] : moves) {
        placed p{to, {}};
        struct stat s {};
        if (::lstat(to.c_str(), &s) == 0 && S_ISREG(s.st_mode))
            for (int attempt = 0; attempt < 8 && p.backup.empty(); ++attempt) {
                const fs::path backup = to.parent_path() / (hidden_name(to, "old") + random_suffix());
                if (::link(to.c_str(), backup.c_str()) == 0) p.backup = backup;
                else if (errno != EEXIST) break;  // no hard links here: no way back for this one
            }
        if (::rename(from.c_str(), to.c_str()) != 0) {
            const int e = errno;
            if (!p.backup.empty()) ::unlink(p.backup.c_str());
            roll_back();
            for (const placed& q : done)
                if (!q.backup.empty()) ::unlink(q.backup.c_str());
            throw input_error(to.string(), 0, "", "cannot rename into place: " + error_text(e) +
                                                      " (no output of this run was kept)");
        }
        done.push_back(p);
    }
    for (auto& f : files_)
        if (!f->written_through_) release(f->slot_);
    for (const placed& p : done)
        if (!p.backup.empty()) ::unlink(p.backup.c_str());
    std::vector<fs::path> synced;
    for (const auto& [from, to] : moves)
        if (std::find(synced.begin(), synced.end(), to.parent_path()) == synced.end()) {
            synced.push_back(to.parent_path());
            sync_directory(to.parent_path());
        }
    for (auto& d : directories_) {
        for (auto& [path, slot] : d->staging) {
            std::error_code ignored;
            fs::remove_all(path, ignored);
        }
        if (d->lock_slot >= 0) {  // the directory is free for the next run
            ::unlink(d->lock.c_str());
            release(d->lock_slot);
        }
    }
    committed_ = true;
}

void write_file_atomically(const fs::path& path, const std::string& contents) {
    run_outputs outputs;
    outputs.file(path, "").stream() << contents;
    outputs.commit();
}

namespace {

// Set once the reader of standard output has closed it (EPIPE): what is
// written after that is dropped.
std::atomic<bool> standard_output_closed{false};

// Standard output's writes, through fopencookie: a closed pipe drops the
// rest; any other failure (a full disk) is the stream's error, as before.
ssize_t write_standard_output(void*, const char* data, std::size_t size) {
    for (std::size_t done = 0; done < size && !standard_output_closed.load();) {
        const ssize_t n = ::write(STDOUT_FILENO, data + done, size - done);
        if (n >= 0) {
            done += static_cast<std::size_t>(n);
        } else if (errno == EPIPE) {
            standard_output_closed.store(true);
        } else if (errno != EINTR) {
            return 0;  // fopencookie's "error": the stream's error flag, errno kept
        }
    }
    return static_cast<ssize_t>(size);
}

}  // namespace

void guard_standard_output() {
    static std::once_flag once;
    std::call_once(once, [] {
        const cookie_io_functions_t io{nullptr, write_standard_output, nullptr, nullptr};
        FILE* guarded = ::fopencookie(nullptr, "w", io);
        if (guarded == nullptr) return;  // stdout as it was: a closed pipe then ends the write with an error
        std::fflush(stdout);
        ::setvbuf(guarded, nullptr, ::isatty(STDOUT_FILENO) ? _IOLBF : _IOFBF, BUFSIZ);
        stdout = guarded;
    });
}

bool standard_output_closed_by_reader() { return standard_output_closed.load(); }

void check_standard_output() {
    errno = 0;
    const bool flushed = std::fflush(stdout) == 0;
    const int error = errno;
    if (flushed && !std::ferror(stdout)) return;
    std::clearerr(stdout);
    throw input_error("standard output", 0, "",
                      "cannot write: " + (error != 0 ? error_text(error) : std::string("a write failed")));
}

void check_standard_output_at_exit() {
    check_standard_output();
    if (standard_output_closed_by_reader())
        throw input_error("standard output", 0, "",
                          "cannot write: " + error_text(EPIPE) +
                              " (its reader closed it: the rest of the output was dropped; the command ran to "
                              "its end and wrote its files)");
}

void remove_unfinished_outputs() noexcept {
    if (registry_owner.load() != ::getpid()) return;  // a forked child: the outputs are its parent's
    for (int kind : {temporary_file, staging_dir, lock_file})
        for (slot& s : slots) {
            if (s.kind.load(std::memory_order_acquire) != kind) continue;
            if (kind == staging_dir)
                remove_directory_now(s.path);
            else
                ::unlink(s.path);
        }
    // Innermost directories first: rmdir fails on a directory that is not empty yet.
    for (bool removed = true; removed;) {
        removed = false;
        for (slot& s : slots)
            if (s.kind.load(std::memory_order_acquire) == created_dir && ::rmdir(s.path) == 0) {
                s.kind.store(free_slot, std::memory_order_release);
                removed = true;
            }
    }
}

running_command::running_command() {
    install_signal_handlers();
    command_in_progress.store(true);
}

running_command::~running_command() { command_in_progress.store(false); }

bool command_running() noexcept { return command_in_progress.load(); }

}  // namespace rayverify
