// An intersector that is a program of its own, in any language: started once
// (/bin/sh -c COMMAND), it reads batches of cases on its standard input and
// answers each batch on its standard output, in the exchange formats
// (corpus/exchange.h). Each batch is a complete cases file (its header says
// how many cases follow); each answer is a complete results file for exactly
// those cases, repeating the batch's precision and fingerprint. The program's
// standard error is left to the terminal.
//
// Like an isolated plugin (plugin/plugin_host.h), a program that exits, is
// killed, does not answer a batch within the timeout (it is then killed), or
// answers with anything but one valid answer per case makes answer() throw
// case_failure naming the command and the batch's first case. The program is
// started in a session of its own; when it ends, every process still in that
// session (what it started and left running, even in another process group)
// is killed.
#pragma once

#include <sys/types.h>

#include <memory>
#include <span>
#include <string>

#include "core/input_error.h"
#include "core/recorded_answer.h"
#include "corpus/exchange.h"

namespace rayverify {

class external_program {
public:
    // Starts the program. JSON lines and CSV only: a pipe carries no npy companion.
    // Throws input_error (field "--command") when it cannot be started.
    external_program(std::string command, exchange_format format, precision prec, double timeout_seconds);
    // Closes its standard input, waits for it to exit (at most the timeout), kills it otherwise.
    ~external_program();
    external_program(const external_program&) = delete;
    external_program& operator=(const external_program&) = delete;

    // The program's answers to `cases` (ids unique within the batch, values
    // already in the program's precision).
    std::shared_ptr<const answer_book> answer(std::span<const corpus_case> cases);

    // After the last batch: closes the program's input and reads its output
    // to the end (killing it past the timeout). Throws input_error (field
    // "--command") when it wrote anything after its answer to the last batch:
    // an extra answer, or trailing output.
    void finish();

    const std::string& command() const { return command_; }
    std::size_t batches() const { return batches_; }

private:
    [[noreturn]] void fail(const std::string& happened, std::span<const corpus_case> cases);
    std::string ended();  // closes the pipes, reaps the program, says how it ended
    void kill_session();  // SIGKILL to every process of the program's session

    std::string command_;
    exchange_format format_;
    precision prec_;
    double timeout_seconds_;
    int to_program_ = -1, from_program_ = -1;
    pid_t pid_ = -1;
    std::size_t batches_ = 0;
    std::string pending_;  // output read past the end of the last answer
};

}  // namespace rayverify
