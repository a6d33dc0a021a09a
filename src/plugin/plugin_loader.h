// Loading a user's intersector from a shared library (rayverify_plugin.h)
// as a registry variant, so that every command audits it like a built-in.
#pragma once

#include <filesystem>

#include "intersectors/registry.h"

namespace rayverify {

// dlopen the library and wrap its functions as a variant: run_double always,
// run_float when the plugin exports rayverify_plugin_intersect_float. The
// variant's functions keep the library loaded for as long as a copy of them
// exists. Throws input_error naming the path (field "--plugin") when the file
// is missing, is not a loadable library, lacks a required symbol, reports
// another ABI version, or describes itself inconsistently (no name, a name
// with whitespace, an unknown query kind).
variant load_plugin(const std::filesystem::path& library);

}  // namespace rayverify
