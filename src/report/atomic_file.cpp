#include "report/atomic_file.h"

#include <cerrno>
#include <cstring>
#include <system_error>

#include "core/input_error.h"

namespace rayverify {

atomic_file::atomic_file(std::filesystem::path path)
    : path_(std::move(path)), temporary_(path_.string() + ".tmp") {
    out_.open(temporary_, std::ios::binary | std::ios::trunc);
    if (!out_) throw input_error(path_.string(), 0, "", std::string("cannot write: ") + std::strerror(errno));
}

atomic_file::~atomic_file() {
    if (committed_) return;
    out_.close();
    std::error_code ignored;
    std::filesystem::remove(temporary_, ignored);
}

void atomic_file::commit() {
    out_.flush();
    const bool written = static_cast<bool>(out_);
    out_.close();
    if (!written) throw input_error(path_.string(), 0, "", "write failed (disk full?)");
    std::error_code error;
    std::filesystem::rename(temporary_, path_, error);
    if (error) throw input_error(path_.string(), 0, "", "cannot rename into place: " + error.message());
    committed_ = true;
}

}  // namespace rayverify
