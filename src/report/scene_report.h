// What `rayverify audit --scene` prints and writes: the scene's summary and
// one table per ray kind (the verdict columns its query can produce, the
// ULP figures it needs), and scene_report.json with the same figures.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "scene/scene.h"
#include "scene/scene_audit.h"

namespace rayverify {

// The text the scene audit prints: the scene, its rays, then each enabled ray
// kind's table and the targets that are not applicable, with why.
std::string scene_audit_text(const scene& s, const scene_audit_result& result);

// scene_report.json (docs/schema/scene-report.schema.json); `command` is the
// command line as recorded.
nlohmann::ordered_json scene_report_json(const scene& s, const scene_audit_result& result, const std::string& command);

}  // namespace rayverify
