// The case the calling thread is running variants on. A plugin that crashes
// or hangs is caught where only the geometry is known (plugin/), so the loops
// that run variants on a case (audit_case, the hunter, the scene audit)
// announce it here and the plugin layer names it in its error, or in the
// message its crash handler writes. One pointer per thread: nothing is copied
// or formatted, and a signal handler may read it.
#pragma once

#include "core/ray_sphere_case.h"

namespace rayverify {

class case_in_progress {
public:
    // `c` must outlive this object.
    explicit case_in_progress(const corpus_case& c) : previous_(current_) { current_ = &c; }
    ~case_in_progress() { current_ = previous_; }
    case_in_progress(const case_in_progress&) = delete;
    case_in_progress& operator=(const case_in_progress&) = delete;

    // nullptr when no case is announced on this thread.
    static const corpus_case* current() { return current_; }

private:
    static inline thread_local const corpus_case* current_ = nullptr;
    const corpus_case* previous_;
};

}  // namespace rayverify
