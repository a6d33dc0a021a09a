// How a child process ended, in words, from its waitpid() status: shared by
// the isolated plugin host (plugin/) and external programs (corpus/).
#pragma once

#include <sys/wait.h>

#include <cstring>
#include <string>

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

}  // namespace rayverify
