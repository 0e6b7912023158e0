#include "io/output.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <locale>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string_view>

#ifdef ISPH_HAVE_HDF5
#include <hdf5.h>
#endif

namespace isph {

namespace {

// `value` with `digits` significant digits in the shortest of fixed and scientific notation,
// independent of the global locale.
std::string format_number(double value, int digits) {
  std::ostringstream out;
  out.imbue(std::locale::classic());
  out << std::setprecision(digits) << value;
  return out.str();
}

std::runtime_error io_error(const std::string& what, int error) {
  return std::runtime_error(what + ": " + std::strerror(error));
}

// Renames `from` to `to`, replacing `to`; on failure removes `from` and throws.
void rename_into_place(const std::string& from, const std::string& to) {
  if (std::rename(from.c_str(), to.c_str()) != 0) {
    const int error = errno;
    std::remove(from.c_str());
    throw io_error("cannot rename " + from + " to " + to, error);
  }
}

std::string json_quote(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\b':
        out += "\\b";
        break;
      case '\f':
        out += "\\f";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char escaped[8];
          std::snprintf(escaped, sizeof escaped, "\\u%04x", static_cast<unsigned>(c));
          out += escaped;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

using JsonEntries = std::vector<std::pair<std::string, std::string>>;

// Sets `key` to a serialised value or, when `object` is given, to a nested object. A new key is
// appended; an existing key keeps its position. objects[k] belongs to the k-th object entry.
void json_assign(JsonEntries& entries, std::vector<bool>& is_object, std::vector<JsonObject>& objects,
                 const std::string& key, std::string serialised, std::optional<JsonObject> object) {
  const auto found =
      std::find_if(entries.begin(), entries.end(), [&](const auto& entry) { return entry.first == key; });
  const auto i = static_cast<std::size_t>(found - entries.begin());
  if (i == entries.size()) {
    entries.emplace_back(key, std::string());
    is_object.push_back(false);
  }
  const auto slot = objects.begin() + std::count(is_object.begin(), is_object.begin() + i, true);
  if (is_object[i] && object) {
    *slot = std::move(*object);
  } else if (is_object[i]) {
    objects.erase(slot);
  } else if (object) {
    objects.insert(slot, std::move(*object));
  }
  is_object[i] = object.has_value();
  entries[i].second = object ? std::string() : std::move(serialised);
}

}  // namespace

void write_file_atomically(const std::string& path, const std::string& content) {
  if (path.empty()) throw std::invalid_argument("write_file_atomically: empty path");
  const std::string tmp = path + ".tmp";
  std::FILE* file = std::fopen(tmp.c_str(), "wb");
  if (file == nullptr) throw io_error("cannot open " + tmp + " for writing", errno);
  const bool written = std::fwrite(content.data(), 1, content.size(), file) == content.size();
  const int write_error = errno;
  const bool closed = std::fclose(file) == 0;
  if (!written || !closed) {
    const int error = written ? errno : write_error;
    std::remove(tmp.c_str());
    throw io_error("cannot write " + tmp, error);
  }
  rename_into_place(tmp, path);
}

// ---------------------------------------------------------------------------------------------

CsvTable::CsvTable(std::string path, std::vector<std::string> columns)
    : path_(std::move(path)), columns_(std::move(columns)) {
  for (const auto& name : columns_) {
    if (name.find_first_of(",\"\r\n") != std::string::npos) {
      throw std::invalid_argument("CSV column name '" + name + "' contains a comma, quote or line break");
    }
  }
}

void CsvTable::add_row(const std::vector<double>& values) {
  if (values.size() != columns_.size()) {
    throw std::invalid_argument("CSV row for " + path_ + " has " + std::to_string(values.size()) + " values for " +
                                std::to_string(columns_.size()) + " columns");
  }
  rows_.push_back(values);
}

std::size_t CsvTable::add_rows_before(const std::string& path, double before) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::string line;
  std::string header;
  for (std::size_t c = 0; c < columns_.size(); ++c) header += (c ? "," : "") + columns_[c];
  if (!std::getline(in, line) || line != header)
    throw std::runtime_error(path + " has the columns '" + line + "', not '" + header + "'");
  std::size_t added = 0;
  for (std::size_t number = 2; std::getline(in, line); ++number) {
    if (line.empty()) continue;
    std::vector<double> row;
    std::istringstream fields(line);
    fields.imbue(std::locale::classic());
    for (std::string cell; std::getline(fields, cell, ',');) {
      char* end = nullptr;
      row.push_back(std::strtod(cell.c_str(), &end));
      if (end == cell.c_str() || *end != '\0')
        throw std::runtime_error(path + ":" + std::to_string(number) + ": '" + cell + "' is not a number");
    }
    if (row.size() != columns_.size())
      throw std::runtime_error(path + ":" + std::to_string(number) + " has " + std::to_string(row.size()) +
                               " values for " + std::to_string(columns_.size()) + " columns");
    if (!(row[0] < before)) break;
    rows_.push_back(std::move(row));
    ++added;
  }
  return added;
}

void CsvTable::flush() const {
  std::ostringstream out;
  out.imbue(std::locale::classic());
  out << std::setprecision(kDigits);
  for (std::size_t c = 0; c < columns_.size(); ++c) out << (c ? "," : "") << columns_[c];
  out << '\n';
  for (const auto& row : rows_) {
    for (std::size_t c = 0; c < row.size(); ++c) out << (c ? "," : "") << row[c];
    out << '\n';
  }
  write_file_atomically(path_, out.str());
}

// ---------------------------------------------------------------------------------------------

JsonObject& JsonObject::set(const std::string& key, double value) {
  json_assign(entries_, is_object_, objects_, key, std::isfinite(value) ? format_number(value, 12) : "null",
              std::nullopt);
  return *this;
}

JsonObject& JsonObject::set(const std::string& key, long long value) {
  json_assign(entries_, is_object_, objects_, key, std::to_string(value), std::nullopt);
  return *this;
}

JsonObject& JsonObject::set(const std::string& key, bool value) {
  json_assign(entries_, is_object_, objects_, key, value ? "true" : "false", std::nullopt);
  return *this;
}

JsonObject& JsonObject::set(const std::string& key, const std::string& value) {
  json_assign(entries_, is_object_, objects_, key, json_quote(value), std::nullopt);
  return *this;
}

JsonObject& JsonObject::set(const std::string& key, const JsonObject& value) {
  // The copy is taken before anything changes, so obj.set("self", obj) is safe.
  json_assign(entries_, is_object_, objects_, key, std::string(), value);
  return *this;
}

// indent > 0: one entry per line, nested objects indented by `indent` more spaces per level.
// indent <= 0: everything on one line without spaces.
std::string JsonObject::dump(int indent) const { return dump_at(indent, 0); }

std::string JsonObject::dump_at(int indent, int level) const {
  if (entries_.empty()) return "{}";
  const bool pretty = indent > 0;
  const std::string inner = pretty ? "\n" + std::string((level + 1) * indent, ' ') : "";
  std::string out = "{";
  std::size_t object = 0;
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    out += (i ? "," : "") + inner + json_quote(entries_[i].first) + (pretty ? ": " : ":");
    out += is_object_[i] ? objects_[object++].dump_at(indent, level + 1) : entries_[i].second;
  }
  if (pretty) out += "\n" + std::string(level * indent, ' ');
  return out + "}";
}

// ---------------------------------------------------------------------------------------------

#ifdef ISPH_HAVE_HDF5
namespace {

// Owns an HDF5 identifier; throws on construction from a failed call.
class H5Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  H5Handle(hid_t id, Closer closer, const std::string& what) : id_(id), closer_(closer) {
    if (id_ < 0) throw std::runtime_error("HDF5: cannot " + what);
  }
  H5Handle(const H5Handle&) = delete;
  H5Handle& operator=(const H5Handle&) = delete;
  ~H5Handle() {
    if (id_ >= 0) closer_(id_);
  }
  hid_t get() const { return id_; }
  // Closes now, so that errors (e.g. while flushing a file) are reported.
  void close(const std::string& what) {
    const herr_t status = closer_(id_);
    id_ = -1;
    if (status < 0) throw std::runtime_error("HDF5: cannot " + what);
  }

 private:
  hid_t id_;
  Closer closer_;
};

void write_dataset(hid_t file, const std::string& path, const std::string& name, const std::vector<hsize_t>& dims,
                   const double* data) {
  const std::string where = "dataset " + name + " in " + path;
  H5Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose,
                 "create the dataspace of " + where);
  H5Handle dataset(H5Dcreate2(file, name.c_str(), H5T_IEEE_F64LE, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                   H5Dclose, "create " + where);
  if (dims.front() > 0 && H5Dwrite(dataset.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0) {
    throw std::runtime_error("HDF5: cannot write " + where);
  }
  dataset.close("close " + where);
}

void write_attribute(hid_t file, const std::string& path, const std::string& name, double value) {
  H5Handle scalar(H5Screate(H5S_SCALAR), H5Sclose, "create a scalar dataspace");
  H5Handle attribute(H5Acreate2(file, name.c_str(), H5T_IEEE_F64LE, scalar.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
                     "create attribute " + name + " in " + path);
  if (H5Awrite(attribute.get(), H5T_NATIVE_DOUBLE, &value) < 0) {
    throw std::runtime_error("HDF5: cannot write attribute " + name + " in " + path);
  }
  attribute.close("close attribute " + name + " in " + path);
}

void write_snapshot_file(const std::string& path, double time, const std::vector<double>& positions,
                         const std::vector<SnapshotField>& fields, const SnapshotAttributes& attributes) {
  const auto n = static_cast<hsize_t>(positions.size() / 3);
  H5Handle file(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose, "create " + path);
  write_dataset(file.get(), path, "position", {n, 3}, positions.data());
  for (const auto& field : fields) {
    std::vector<hsize_t> dims{n};
    if (field.components > 1) dims.push_back(static_cast<hsize_t>(field.components));
    write_dataset(file.get(), path, field.name, dims, field.data.data());
  }
  write_attribute(file.get(), path, "time", time);
  for (const auto& [name, value] : attributes) write_attribute(file.get(), path, name, value);
  file.close("close " + path);
}

std::string xml_escape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string hdf_data_item(const std::string& dimensions, const std::string& file, const std::string& dataset) {
  return "<DataItem Format=\"HDF\" NumberType=\"Float\" Precision=\"8\" Dimensions=\"" + dimensions + "\">" +
         xml_escape(file + ":/" + dataset) + "</DataItem>";
}

}  // namespace
#endif

SnapshotWriter::SnapshotWriter(std::string dir, int dimension) : dir_(std::move(dir)), dimension_(dimension) {
  if (dimension_ != 2 && dimension_ != 3) {
    throw std::invalid_argument("SnapshotWriter: dimension must be 2 or 3, not " + std::to_string(dimension_));
  }
}

bool SnapshotWriter::available() {
#ifdef ISPH_HAVE_HDF5
  return true;
#else
  return false;
#endif
}

#ifdef ISPH_HAVE_HDF5
namespace {

// The fields' names and components, checked: a name once, no path, and n values per component.
std::vector<std::pair<std::string, int>> field_layout(const std::vector<SnapshotField>& fields, std::size_t n) {
  std::vector<std::pair<std::string, int>> layout;
  for (const auto& field : fields) {
    if (field.name.empty() || field.name == "." || field.name == "position" ||
        field.name.find('/') != std::string::npos) {
      throw std::invalid_argument("snapshot field name '" + field.name + "' is not allowed");
    }
    if (std::any_of(layout.begin(), layout.end(), [&](const auto& entry) { return entry.first == field.name; })) {
      throw std::invalid_argument("snapshot field '" + field.name + "' is given twice");
    }
    if (field.components < 1 || field.data.size() != n * field.components) {
      throw std::invalid_argument("snapshot field '" + field.name + "' has " + std::to_string(field.data.size()) +
                                  " values for " + std::to_string(n) + " particles x " +
                                  std::to_string(field.components) + " components");
    }
    layout.emplace_back(field.name, field.components);
  }
  return layout;
}

}  // namespace

// The XDMF index of every snapshot written so far, which ParaView opens as one time series.
std::string SnapshotWriter::xdmf_index() const {
  std::string xmf =
      "<?xml version=\"1.0\" ?>\n"
      "<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
      "<Xdmf Version=\"2.0\">\n"
      " <Domain>\n"
      "  <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t s = 0; s < times_.size(); ++s) {
    const std::string points = std::to_string(sizes_[s]);
    const std::string grid = files_[s].substr(0, files_[s].size() - 3);  // without ".h5"
    xmf += "   <Grid Name=\"" + grid + "\" GridType=\"Uniform\">\n";
    xmf += "    <Time Value=\"" + format_number(times_[s], 15) + "\"/>\n";
    xmf += "    <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" + points + "\" NodesPerElement=\"1\"/>\n";
    xmf += "    <Geometry GeometryType=\"XYZ\">\n";
    xmf += "     " + hdf_data_item(points + " 3", files_[s], "position") + "\n";
    xmf += "    </Geometry>\n";
    for (const auto& [field, components] : layouts_[s]) {
      const char* type = components == 1 ? "Scalar" : components == 3 ? "Vector" : "Matrix";
      const std::string dims = components == 1 ? points : points + " " + std::to_string(components);
      xmf += "    <Attribute Name=\"" + xml_escape(field) + "\" AttributeType=\"" + type + "\" Center=\"Node\">\n";
      xmf += "     " + hdf_data_item(dims, files_[s], field) + "\n";
      xmf += "    </Attribute>\n";
    }
    xmf += "   </Grid>\n";
  }
  xmf +=
      "  </Grid>\n"
      " </Domain>\n"
      "</Xdmf>\n";
  return xmf;
}

void SnapshotWriter::write(double time, const std::vector<std::array<double, 3>>& positions,
                           const std::vector<SnapshotField>& fields, const SnapshotAttributes& attributes) {
  if (dir_.empty()) throw std::logic_error("SnapshotWriter::write: no output directory");
  const std::size_t n = positions.size();
  std::vector<std::pair<std::string, int>> layout = field_layout(fields, n);
  std::vector<double> flat(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    flat[3 * i] = positions[i][0];
    flat[3 * i + 1] = positions[i][1];
    flat[3 * i + 2] = dimension_ == 2 ? 0.0 : positions[i][2];
  }

  const std::filesystem::path snapshots = std::filesystem::path(dir_) / "snapshots";
  std::filesystem::create_directories(snapshots);
  char name[32];
  std::snprintf(name, sizeof name, "snapshot_%05d.h5", count());
  const std::string path = (snapshots / name).string();
  const std::string tmp = path + ".tmp";
  try {
    write_snapshot_file(tmp, time, flat, fields, attributes);
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
  rename_into_place(tmp, path);

  times_.push_back(time);
  files_.push_back(name);
  layouts_.push_back(std::move(layout));
  sizes_.push_back(static_cast<long long>(n));

  write_file_atomically((snapshots / "snapshots.xmf").string(), xdmf_index());
}
#else
void SnapshotWriter::write(double, const std::vector<std::array<double, 3>>&, const std::vector<SnapshotField>&,
                           const SnapshotAttributes&) {}
#endif

std::size_t SnapshotData::size() const { return field("position").data.size() / 3; }

const SnapshotField& SnapshotData::field(const std::string& name) const {
  const auto it = fields.find(name);
  if (it == fields.end()) throw std::runtime_error(path + " has no dataset '" + name + "'");
  return it->second;
}

std::vector<long long> SnapshotData::rows_by_id() const {
  const SnapshotField& ids = field("id");
  double max_id = -1;
  for (const double id : ids.data) max_id = std::max(max_id, id);
  std::vector<long long> row(static_cast<std::size_t>(max_id + 1), -1);
  for (std::size_t r = 0; r < ids.data.size(); ++r)
    if (ids.data[r] >= 0) row[static_cast<std::size_t>(ids.data[r])] = static_cast<long long>(r);
  return row;
}

#ifdef ISPH_HAVE_HDF5
namespace {

herr_t collect_attribute_name(hid_t, const char* name, const H5A_info_t*, void* names) {
  static_cast<std::vector<std::string>*>(names)->push_back(name);
  return 0;
}

// The names of the links in the root group (the datasets of a snapshot) or of the root's attributes.
std::vector<std::string> root_names(hid_t file, const std::string& path, bool attributes) {
  std::vector<std::string> names;
  if (attributes) {
    if (H5Aiterate2(file, H5_INDEX_NAME, H5_ITER_INC, nullptr, collect_attribute_name, &names) < 0)
      throw std::runtime_error("HDF5: cannot list the attributes of " + path);
    return names;
  }
  H5G_info_t info;
  if (H5Gget_info(file, &info) < 0) throw std::runtime_error("HDF5: cannot read the root of " + path);
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    char name[256];
    const ssize_t length = H5Lget_name_by_idx(file, ".", H5_INDEX_NAME, H5_ITER_INC, i, name, sizeof name, H5P_DEFAULT);
    if (length < 0 || length >= static_cast<ssize_t>(sizeof name))
      throw std::runtime_error("HDF5: cannot read a dataset name in " + path);
    names.emplace_back(name);
  }
  return names;
}

}  // namespace

SnapshotData read_snapshot(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw std::runtime_error("snapshot " + path + " does not exist");
  SnapshotData out;
  out.path = path;
  H5Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, "open " + path);
  for (const auto& name : root_names(file.get(), path, false)) {
    const std::string where = "dataset " + name + " in " + path;
    H5Handle dataset(H5Dopen2(file.get(), name.c_str(), H5P_DEFAULT), H5Dclose, "open " + where);
    H5Handle space(H5Dget_space(dataset.get()), H5Sclose, "read the dataspace of " + where);
    hsize_t dims[2] = {0, 1};
    const int rank = H5Sget_simple_extent_dims(space.get(), dims, nullptr);
    if (rank < 1 || rank > 2) throw std::runtime_error("HDF5: " + where + " has rank " + std::to_string(rank));
    SnapshotField field{name, static_cast<int>(rank == 2 ? dims[1] : 1),
                        std::vector<double>(static_cast<std::size_t>(dims[0] * (rank == 2 ? dims[1] : 1)))};
    if (dims[0] > 0 && H5Dread(dataset.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, field.data.data()) < 0)
      throw std::runtime_error("HDF5: cannot read " + where);
    out.fields.emplace(name, std::move(field));
  }
  for (const auto& name : root_names(file.get(), path, true)) {
    H5Handle attribute(H5Aopen(file.get(), name.c_str(), H5P_DEFAULT), H5Aclose,
                       "open attribute " + name + " in " + path);
    double value = 0;
    if (H5Aread(attribute.get(), H5T_NATIVE_DOUBLE, &value) < 0)
      throw std::runtime_error("HDF5: cannot read attribute " + name + " in " + path);
    out.attributes[name] = value;
  }
  if (!out.attributes.count("time")) throw std::runtime_error(path + " has no attribute 'time': not a snapshot");
  out.time = out.attributes["time"];
  out.field("position");
  return out;
}
#else
SnapshotData read_snapshot(const std::string& path) {
  throw std::runtime_error("cannot read " + path + ": this build has no HDF5");
}
#endif

std::string newest_snapshot(const std::string& run_dir) {
  namespace fs = std::filesystem;
  const fs::path folder =
      fs::is_directory(fs::path(run_dir) / "snapshots") ? fs::path(run_dir) / "snapshots" : fs::path(run_dir);
  std::vector<std::pair<long long, fs::path>> found;  // snapshot_NNNNN.h5 by its number
  for (const auto& entry : fs::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    constexpr std::string_view prefix = "snapshot_", suffix = ".h5";
    if (!entry.is_regular_file() || name.size() <= prefix.size() + suffix.size() || !name.starts_with(prefix) ||
        !name.ends_with(suffix))
      continue;
    const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
    if (digits.find_first_not_of("0123456789") == std::string::npos)
      found.emplace_back(std::stoll(digits), entry.path());
  }
  std::sort(found.begin(), found.end(), std::greater<>());
  std::string passed_over;
  for (const auto& [number, file] : found) {
    try {
      read_snapshot(file.string());
      if (!passed_over.empty()) std::fprintf(stderr, "restart: passed over %s (unreadable)\n", passed_over.c_str());
      return file.string();
    } catch (const std::exception& e) {
      passed_over += (passed_over.empty() ? "" : ", ") + file.filename().string() + ": " + e.what();
    }
  }
  throw std::runtime_error("restart: no snapshot in " + folder.string() + " reads back whole" +
                           (passed_over.empty() ? "" : " (" + passed_over + ")"));
}

}  // namespace isph
