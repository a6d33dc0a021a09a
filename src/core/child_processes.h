// The processes rayverify starts, kept on a leash (docs/outputs.md, "Children").
//
// A program run with --command, or an engine's node, is the first process of
// a session of its own; what it starts inherits that session unless it calls
// setsid(). rayverify is the child subreaper of everything it starts
// (PR_SET_CHILD_SUBREAPER), so a process that escapes by a double fork into a
// new session is re-parented to rayverify, not to init, and is still found:
//
// - end_program_session(P) kills (SIGKILL) every process of P's session,
//   every descendant of P whatever its session, and every process rayverify
//   adopted that it did not start itself; then reaps what it adopted.
// - The cleanup signals (SIGINT, SIGTERM, SIGHUP, SIGQUIT) do the same for
//   every program session still open, from the signal handler (raw system
//   calls only), before the signal ends rayverify.
//
// What cannot be reached: a process that asked another one (systemd, a
// D-Bus service, `at`) to start something on its behalf; that is not a child.
#pragma once

#include <sys/types.h>

namespace rayverify {

// Makes rayverify the subreaper of its descendants (Linux; a no-op elsewhere).
void become_child_subreaper();

// A process rayverify forked: kept out of the adopted processes that
// end_program_session kills (an isolated plugin's host, a program).
void started_child(pid_t pid);
void child_ended(pid_t pid);

// A program started as the leader of session `session` (its pid): killed
// with its session and descendants by the cleanup signals until it ends.
void program_session_opened(pid_t session);
// Kills the session `session`, the descendants of its leader and the
// processes rayverify adopted, reaps those, and forgets the session.
void end_program_session(pid_t session);

// For the signal handler (async-signal-safe): the same for every open session.
void end_program_sessions_now() noexcept;

}  // namespace rayverify
