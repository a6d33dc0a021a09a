// A report.json's result for one variant in one precision, for tests that
// compare targets of one audit.
#pragma once

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

namespace rayverify::test_support {

inline const nlohmann::json& result_for(const nlohmann::json& report, const std::string& variant,
                                        const std::string& precision) {
    for (const nlohmann::json& r : report.at("results"))
        if (r.at("variant") == variant && r.at("precision") == precision) return r;
    ADD_FAILURE() << "no result for " << variant << "/" << precision;
    static const nlohmann::json none = nlohmann::json::object();
    return none;
}

}  // namespace rayverify::test_support
