#include "core/child_processes.h"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>

namespace rayverify {

namespace {

// Slots hold a pid, 0 when free. Fixed arrays: the signal handler reads them.
constexpr int slot_count = 64;
std::atomic<pid_t> open_sessions[slot_count];
std::atomic<pid_t> started_children[slot_count];

void take_slot(std::atomic<pid_t>* slots, pid_t pid) {
    for (int i = 0; i < slot_count; ++i) {
        pid_t free = 0;
        if (slots[i].compare_exchange_strong(free, pid)) return;
    }
}

void free_slot(std::atomic<pid_t>* slots, pid_t pid) {
    for (int i = 0; i < slot_count; ++i) {
        pid_t held = pid;
        if (slots[i].compare_exchange_strong(held, 0)) return;
    }
}

bool in_slots(const std::atomic<pid_t>* slots, pid_t pid) {
    for (int i = 0; i < slot_count; ++i)
        if (slots[i].load() == pid) return true;
    return false;
}

struct process_entry {
    pid_t pid, parent, session;
};
constexpr int max_processes = 4096;

// A whole number at the start of `text` (at most `size` bytes), skipping
// spaces first; `at` moves past it. False when there is none.
bool read_number(const char* text, int size, int& at, long& value) {
    while (at < size && text[at] == ' ') ++at;
    const bool negative = at < size && text[at] == '-';
    if (negative) ++at;
    if (at >= size || text[at] < '0' || text[at] > '9') return false;
    value = 0;
    while (at < size && text[at] >= '0' && text[at] <= '9') value = value * 10 + (text[at++] - '0');
    if (negative) value = -value;
    return true;
}

// Every process of /proc as (pid, parent, session), with system calls that a
// signal handler may make (no allocation, no stdio).
int read_processes(process_entry* out, int capacity) noexcept {
    const int dir = ::open("/proc", O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dir < 0) return 0;
    int count = 0;
    alignas(8) char entries[4096];
    for (long n; count < capacity && (n = ::syscall(SYS_getdents64, dir, entries, sizeof entries)) > 0;) {
        for (long at = 0; at < n && count < capacity;) {
            const auto* e = reinterpret_cast<const struct dirent64*>(entries + at);
            at += e->d_reclen;
            // "/proc/" + the name + "/stat", the name digits only.
            char path[48] = "/proc/";
            int length = 6;
            bool digits = e->d_name[0] != '\0';
            for (const char* c = e->d_name; *c != '\0' && length < 32; ++c) {
                digits = digits && *c >= '0' && *c <= '9';
                path[length++] = *c;
            }
            if (!digits) continue;
            for (const char* c = "/stat"; *c != '\0'; ++c) path[length++] = *c;
            path[length] = '\0';
            const int fd = ::open(path, O_RDONLY | O_CLOEXEC);
            if (fd < 0) continue;  // it ended meanwhile
            char stat[512];
            const ssize_t size = ::read(fd, stat, sizeof stat);
            ::close(fd);
            if (size <= 0) continue;
            // "pid (name) state parent group session ...": the name may hold
            // spaces and parentheses, so the fields start after the last ')'.
            int close_paren = -1;
            for (int i = 0; i < size; ++i)
                if (stat[i] == ')') close_paren = i;
            if (close_paren < 0 || close_paren + 3 >= size) continue;
            int at_field = close_paren + 3;  // past ") S"
            long pid = 0, parent = 0, group = 0, session = 0;
            int at_pid = 0;
            if (!read_number(stat, static_cast<int>(size), at_pid, pid) ||
                !read_number(stat, static_cast<int>(size), at_field, parent) ||
                !read_number(stat, static_cast<int>(size), at_field, group) ||
                !read_number(stat, static_cast<int>(size), at_field, session))
                continue;
            out[count++] = {static_cast<pid_t>(pid), static_cast<pid_t>(parent), static_cast<pid_t>(session)};
        }
    }
    ::close(dir);
    return count;
}

// SIGKILL to every process of a session in `sessions` (or the leader of one),
// every descendant of those, and, with `adopted`, every child of rayverify it
// did not start itself, with their descendants. Returns how many it marked;
// `marked[i]` says which of `table` (filled here) were.
int kill_tree(const pid_t* sessions, int session_count, bool adopted, process_entry* table, bool* marked,
              int& count) noexcept {
    const pid_t self = ::getpid();
    count = read_processes(table, max_processes);
    int killed = 0;
    for (int i = 0; i < count; ++i) {
        marked[i] = false;
        for (int s = 0; s < session_count; ++s)
            if (table[i].session == sessions[s] || table[i].pid == sessions[s]) marked[i] = true;
        if (adopted && table[i].parent == self && !in_slots(started_children, table[i].pid)) marked[i] = true;
        if (table[i].pid == self) marked[i] = false;
    }
    // Descendants of what is marked, whatever their session.
    for (bool grew = true; grew;) {
        grew = false;
        for (int i = 0; i < count; ++i) {
            if (marked[i] || table[i].pid == self) continue;
            for (int j = 0; j < count; ++j)
                if (marked[j] && table[j].pid == table[i].parent) {
                    marked[i] = grew = true;
                    break;
                }
        }
    }
    for (int i = 0; i < count; ++i)
        if (marked[i] && ::kill(table[i].pid, SIGKILL) == 0) ++killed;
    return killed;
}

}  // namespace

void become_child_subreaper() { ::prctl(PR_SET_CHILD_SUBREAPER, 1); }

void started_child(pid_t pid) { take_slot(started_children, pid); }
void child_ended(pid_t pid) { free_slot(started_children, pid); }

void program_session_opened(pid_t session) { take_slot(open_sessions, session); }

void end_program_session(pid_t session) {
    static process_entry table[max_processes];
    static bool marked[max_processes];
    int count = 0;
    kill_tree(&session, 1, true, table, marked, count);
    // Reap what rayverify adopted and killed (its own children reap themselves).
    const pid_t self = ::getpid();
    for (int i = 0; i < count; ++i)
        if (marked[i] && table[i].parent == self && !in_slots(started_children, table[i].pid))
            while (::waitpid(table[i].pid, nullptr, 0) < 0 && errno == EINTR) {
            }
    free_slot(open_sessions, session);
}

void end_program_sessions_now() noexcept {
    pid_t sessions[slot_count];
    int session_count = 0;
    for (int i = 0; i < slot_count; ++i)
        if (const pid_t s = open_sessions[i].load(); s != 0) sessions[session_count++] = s;
    if (session_count == 0) return;
    // Its own tables: the handler may interrupt end_program_session.
    static process_entry table[max_processes];
    static bool marked[max_processes];
    int count = 0;
    kill_tree(sessions, session_count, true, table, marked, count);
}

}  // namespace rayverify
