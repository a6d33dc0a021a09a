// The compact audit summary (`rayverify audit --summary`): one line per
// variant family, for a terminal or a README. Rendering only.
#pragma once

#include <string>
#include <vector>

#include "compare/audit.h"

namespace rayverify {

// A variant's family: the shortest other audited name it extends with '_'
// (hearn_baker_unit_nearest → hearn_baker), else its own name.
std::string variant_family(const std::string& name, const std::vector<std::string>& names);

// One line per family: its member with the fewest wrong answers (share of the
// cases it is scored on, both precisions together), that member's wrong
// answers per precision, its commonest disagreement and its largest
// nearest-root error per precision; then the member with the most.
std::string render_family_summary(const audit_totals& totals);

}  // namespace rayverify
