// Child processes, shared by the isolated plugin host (plugin/) and external
// programs (corpus/): deadlines, reaping one within a deadline, and how it
// ended in words, from its waitpid() status.
#pragma once

#include <sys/wait.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <optional>
#include <string>
#include <thread>

namespace rayverify {

// "was killed by SIGSEGV (Segmentation fault)", "exited with status 3", "ended".
inline std::string describe_wait_status(int status) {
    if (WIFSIGNALED(status)) {
        const int signal = WTERMSIG(status);
        const char* name = sigabbrev_np(signal);
        const char* description = sigdescr_np(signal);
        return name ? "was killed by SIG" + std::string(name) + " (" + (description ? description : "?") + ")"
                    : "was killed by signal " + std::to_string(signal);
    }
    if (WIFEXITED(status)) return "exited with status " + std::to_string(WEXITSTATUS(status));
    return "ended";
}

// `seconds` from now (at most 10^7 s: no overflow of the clock's ticks).
inline std::chrono::steady_clock::time_point deadline_after(double seconds) {
    const double bounded = !(seconds < 1e7) ? 1e7 : std::max(seconds, 0.0);
    return std::chrono::steady_clock::now() +
           std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(bounded));
}

// Waits up to `seconds` for child `pid` to end; past that, sends SIGKILL to
// `kill_target` (the pid, or −pid for its process group) and reaps it. The
// waitpid() status, or nullopt when the child cannot be waited for.
inline std::optional<int> reap_child(pid_t pid, pid_t kill_target, double seconds) {
    const auto deadline = deadline_after(seconds);
    int status = 0;
    for (;;) {
        const pid_t reaped = ::waitpid(pid, &status, WNOHANG);
        if (reaped == pid) return status;
        if (reaped < 0 && errno != EINTR) return std::nullopt;
        if (std::chrono::steady_clock::now() >= deadline) {
            ::kill(kill_target, SIGKILL);
            while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
            }
            return status;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
}

}  // namespace rayverify
