#pragma once
// The keys of the case file's lists and of the tables inside them ([[materials]]; [[bodies]] with their
// shape, clamps, initial_velocity and motion; [[loads]] with their region; [[probes]]; [[open_boundaries]]) and of
// [periodic], each declared once (list_schema.cpp, list_schema_bodies.cpp) as a key of the schema
// (schema.hpp), with the elements it is for (a body's kind, a material's model, a motion's type, the
// dimension). Rules across the keys of one element (one of youngs_modulus and bulk_modulus, min < max)
// are checked by the loader after its keys.
#include <string>
#include <utility>
#include <vector>

#include "io/case.hpp"
#include "io/schema.hpp"

namespace isph {

const std::vector<SchemaKey<MaterialSpec>>& material_keys();
const std::vector<SchemaKey<BodySpec>>& body_keys();
const std::vector<SchemaKey<Shape>>& shape_keys();
const std::vector<SchemaKey<InitialVelocitySpec>>& initial_velocity_keys();
const std::vector<SchemaKey<MotionSpec>>& motion_keys();
const std::vector<SchemaKey<LoadSpec>>& load_keys();
const std::vector<SchemaKey<ProbeSpec>>& probe_keys();
const std::vector<SchemaKey<OpenBoundarySpec>>& open_boundary_keys();
const std::vector<SchemaKey<PeriodicSpec>>& periodic_keys();

// The TOML text of an element's keys that apply to it, `key = value` each (for the resolved case), and
// of one value as an inline table or array.
std::vector<std::pair<std::string, std::string>> material_entries(const MaterialSpec&, int dimension);
std::vector<std::pair<std::string, std::string>> body_entries(const BodySpec&, int dimension);
std::vector<std::pair<std::string, std::string>> load_entries(const LoadSpec&, int dimension);
std::vector<std::pair<std::string, std::string>> probe_entries(const ProbeSpec&, int dimension);
std::vector<std::pair<std::string, std::string>> open_boundary_entries(const OpenBoundarySpec&, int dimension);
std::vector<std::pair<std::string, std::string>> periodic_entries(const PeriodicSpec&, int dimension);

// The tables the docs generate: "materials", "bodies", "shape", "initial_velocity", "motion", "loads",
// "probes", "open_boundaries", "periodic".
const std::vector<std::string>& list_tables();
// The markdown table of one of them.
std::string list_key_reference(const std::string& table);

}  // namespace isph
