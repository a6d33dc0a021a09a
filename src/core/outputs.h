// Every file a run writes, as one transaction (docs/outputs.md).
//
// A regular file is written to a temporary of its own in the target's
// directory (created exclusively, never through a link), and all of a run's
// files are flushed, synced and renamed into place together by commit(), or
// none is: an error, an exception, SIGINT/SIGTERM/SIGHUP/SIGQUIT/SIGPIPE, or
// a plugin that crashes or calls exit() leaves no temporary, no partial file
// and no directory the run created. A device, pipe or terminal cannot be
// rolled back: it is written through as the output is produced, and a failed
// write there is an error all the same. An output directory is locked against
// a second run while this one writes into it. Outputs that would overwrite an
// input or another output are refused when they are declared, before any work.
#pragma once

#include <filesystem>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

namespace rayverify {

// One output of a run_outputs: written through stream(). A write that fails
// (a full disk, a closed pipe) throws input_error from the stream's operation.
class output_file {
public:
    explicit output_file(std::filesystem::path path, std::string option);
    ~output_file();
    output_file(const output_file&) = delete;
    output_file& operator=(const output_file&) = delete;

    std::ostream& stream();
    const std::filesystem::path& path() const { return path_; }
    // A device, pipe or terminal (or a link to one): written through, not renamed.
    bool written_through() const { return written_through_; }

private:
    friend class run_outputs;
    struct buffer;

    std::filesystem::path path_;    // as given, for messages
    std::filesystem::path target_;  // the file renamed over (a link's final target)
    std::string option_;
    bool written_through_ = false;
    int fd_ = -1;
    int slot_ = -1;  // the temporary's entry in the cleanup registry
    std::filesystem::path temporary_;
    std::unique_ptr<buffer> buffer_;
    std::unique_ptr<std::ostream> stream_;
};

class run_outputs {
public:
    run_outputs();
    // Unless committed: every temporary, staged file, lock and directory this run created is removed.
    ~run_outputs();
    run_outputs(const run_outputs&) = delete;
    run_outputs& operator=(const run_outputs&) = delete;

    // What the run reads. An output may not be the same file as an input
    // (by device and inode, or by path when it does not exist yet); a
    // directory of corpus files (`corpus_directory`) may not be an output
    // directory nor receive an output named *.txt or *.csv, which the next
    // audit of that directory would read as a corpus file.
    void input(const std::filesystem::path& path, const std::string& option, bool corpus_directory = false);

    // A directory for outputs (--report DIR, render -o DIR): created with its
    // parents when missing (removed again unless committed) and locked until
    // the run ends: a second run gets an error naming this one's process,
    // host and command. Throws input_error naming `option`.
    void directory(const std::filesystem::path& dir, const std::string& option);

    // An output file, opened now (as a temporary for a regular file). Throws
    // input_error naming the path and `option` when it is a directory, the
    // same file as an input, another output or standard output, or cannot be
    // created. The reference stays valid until this object is destroyed.
    output_file& file(const std::filesystem::path& path, const std::string& option);

    // A private directory inside `dir` (declared with directory()) for files
    // another program writes (the plots); removed with everything in it.
    std::filesystem::path staging_directory(const std::filesystem::path& dir);
    // A file written in the staging directory, renamed to `target` on commit.
    void adopt(const std::filesystem::path& staged, const std::filesystem::path& target);

    // Flushes and syncs every file, then renames them all into place (an
    // existing file replaced by each is restored if a later rename fails),
    // syncs the directories, keeps created directories and releases the
    // locks. Throws input_error naming the file when a write, sync or rename
    // fails; nothing is then in place.
    void commit();

private:
    struct entry;
    struct owned_directory;
    void check_against_inputs(const std::filesystem::path& path, const std::string& option, bool directory) const;

    std::vector<std::unique_ptr<output_file>> files_;
    std::vector<std::pair<std::filesystem::path, std::filesystem::path>> adopted_;  // staged → target
    std::vector<std::unique_ptr<owned_directory>> directories_;
    std::vector<std::unique_ptr<entry>> inputs_;
    std::vector<std::filesystem::path> declared_;  // resolved output paths, for the same-output check
    bool committed_ = false;
};

// Writes `contents` to `path` as a run of one output.
void write_file_atomically(const std::filesystem::path& path, const std::string& contents);

// Standard output written through a guard (main calls this first): when its
// reader closes the pipe (`rayverify audit --report d | head`), the rest of
// the output is dropped and the command runs to its end, files included;
// check_standard_output_at_exit then makes the broken pipe the exit status.
void guard_standard_output();
bool standard_output_closed_by_reader();

// Flushes standard output; throws input_error ("standard output") when a write
// to it failed (a full disk, /dev/full, RLIMIT_FSIZE). Every command calls it
// before committing its files: a table lost that way never comes with files
// that look complete. A pipe closed by its reader is not such a failure.
void check_standard_output();
// The same, and a pipe closed by its reader is an error too (exit 2): main
// calls it once the command is done.
void check_standard_output_at_exit();

// Async-signal-safe: removes every unfinished output of every live
// run_outputs of this process (temporaries, staged files, locks, then the
// directories created). For the signal and exit hooks (here and in plugin/);
// does nothing in a forked child.
void remove_unfinished_outputs() noexcept;

// A command running, as main marks it: the signal handlers that remove
// unfinished outputs are installed (and SIGXFSZ ignored, so that a file over
// RLIMIT_FSIZE is a write error reported like a full disk), and until this
// object ends, an exit() is not the command's own (plugin/ reports it).
class running_command {
public:
    running_command();
    ~running_command();
    running_command(const running_command&) = delete;
    running_command& operator=(const running_command&) = delete;
};
bool command_running() noexcept;

}  // namespace rayverify
