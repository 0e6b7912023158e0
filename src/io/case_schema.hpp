#pragma once
// The settings of a case file, each key declared once (docs/CASES.md, "Settings") as a key of the schema
// (schema.hpp) with its section: the loader reads and checks the settings from this table, the resolved
// case is written from it, and docs/CASES.md's key tables are generated from it (`isph keys`). The lists
// (materials, bodies, loads, probes) and [periodic] are declared by list_schema.hpp; the cross-key rules
// of a section (a preconditioner that its backend must offer, for one) are checked by the loader after
// the section's keys.
#include <string>
#include <vector>

#include "io/case.hpp"
#include "io/schema.hpp"

namespace isph {

using SettingKey = SchemaKey<CaseSpec>;

// Every settings key, in the order of the resolved case and the docs.
const std::vector<SettingKey>& case_keys();
// The settings sections in that order, the top level ("") first.
const std::vector<std::string>& case_sections();

// The markdown table of a section's keys (docs/CASES.md).
std::string key_reference(const std::string& section);
// `document` with every block between "<!-- keys SECTION -->" and "<!-- end keys -->" regenerated.
// Throws std::runtime_error naming a section without a block or an unknown one.
std::string with_key_reference(const std::string& document);

}  // namespace isph
