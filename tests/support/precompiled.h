// The third-party and standard headers most test files include, compiled
// once per build into a precompiled header that every test executable reuses
// (tests/CMakeLists.txt): parsing GoogleTest, nlohmann-json and fmt was
// about a second and a half of each test file's compile. Only headers whose
// meaning no test changes with a macro of its own; rayverify's headers stay
// out, so that a test sees them exactly as it includes them.
#pragma once

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>
