// Internal to plugin/: an isolated plugin, opened and called in a child
// process (load_plugin with plugin_isolation::child_process).
//
// The child is forked, without exec, when the plugin is loaded: it opens the
// library, sends back its description, then answers one call at a time over
// a socket pair until rayverify closes its end. Both ends are one process
// image, so a call's inputs and results cross as their bytes: exactly.
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <span>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "plugin/plugin_library.h"
#include "plugin/plugin_loader.h"

namespace rayverify::plugin_internal {

class plugin_host {
public:
    // Forks the child and waits (at most timeout_seconds) for its description.
    // Throws input_error naming the library when it cannot be used, or when
    // the child dies or does not answer while opening it. The child runs the
    // plugin's every call in the environment `environment` chosen for it by
    // name, else in the one its library set when loaded (the child computes
    // nothing else).
    plugin_host(std::filesystem::path library, double timeout_seconds, const fp_environment_choice& environment);
    // Closes the socket; the child exits at the end of file and is reaped.
    ~plugin_host();
    plugin_host(const plugin_host&) = delete;
    plugin_host& operator=(const plugin_host&) = delete;

    const plugin_description& description() const { return description_; }

    // The plugin's float or double function on s with (tmin, tmax). Throws
    // plugin_failure when the child dies or does not answer within the
    // timeout (it is then killed). `interval_asked`: (tmin, tmax) is the
    // case's own interval, so a failure's inputs keep it.
    root_pair<float> call(const ray_sphere<float>& s, float tmin, float tmax, bool interval_asked);
    root_pair<double> call(const ray_sphere<double>& s, double tmin, double tmax, bool interval_asked);

    // A version 2 plugin's batch function on `cases`, answers into `out`
    // (read under `promises`: a point answer's t is derived). Throws
    // plugin_failure as call() does, naming the batch.
    void call_batch(std::span<const batch_case<float>> cases, std::span<answer<float>> out, const contract& promises);
    void call_batch(std::span<const batch_case<double>> cases, std::span<answer<double>> out, const contract& promises);

private:
    template <class T>
    void batch_in(std::span<const batch_case<T>> cases, std::span<answer<T>> out, const contract& promises);
    template <class T, bool segments>
    void batch_of(std::span<const batch_case<T>> cases, std::span<answer<T>> out, const contract& promises);
    template <class T>
    root_pair<T> call_in(const ray_sphere<T>& s, T tmin, T tmax, bool interval_asked);
    // Closes the socket, reaps the child (which exits at the end of file) and says how it ended.
    std::string ended();
    std::string timed_out();  // kills the child and says so

    std::filesystem::path library_;
    double timeout_seconds_;
    int fd_ = -1;    // our end of the socket pair; -1 once the child is gone
    pid_t pid_ = -1;  // -1 once reaped
    plugin_description description_;
};

}  // namespace rayverify::plugin_internal
