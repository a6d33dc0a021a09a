// An output file that appears whole or not at all: written to "<path>.tmp"
// beside the target, renamed over it on commit(), removed if never committed
// (an error or exception part way leaves no partial output).
#pragma once

#include <filesystem>
#include <fstream>

namespace rayverify {

class atomic_file {
public:
    // Throws input_error when the temporary cannot be created.
    explicit atomic_file(std::filesystem::path path);
    ~atomic_file();
    atomic_file(const atomic_file&) = delete;
    atomic_file& operator=(const atomic_file&) = delete;

    std::ostream& stream() { return out_; }
    // Flush, close and rename into place. Throws input_error on failure.
    void commit();

private:
    std::filesystem::path path_, temporary_;
    std::ofstream out_;
    bool committed_ = false;
};

}  // namespace rayverify
