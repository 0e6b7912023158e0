#include "io/output.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <locale>
#include <optional>
#include <sstream>
#include <stdexcept>

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
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\b': out += "\\b"; break;
      case '\f': out += "\\f"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
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
void json_assign(JsonEntries& entries, std::vector<bool>& is_object,
                 std::vector<JsonObject>& objects, const std::string& key,
                 std::string serialised, std::optional<JsonObject> object) {
  const auto found = std::find_if(entries.begin(), entries.end(),
                                  [&](const auto& entry) { return entry.first == key; });
  const auto i = static_cast<std::size_t>(found - entries.begin());
  if (i == entries.size()) {
    entries.emplace_back(key, std::string());
    is_object.push_back(false);
  }
  const auto slot =
      objects.begin() + std::count(is_object.begin(), is_object.begin() + i, true);
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
      throw std::invalid_argument("CSV column name '" + name +
                                  "' contains a comma, quote or line break");
    }
  }
}

void CsvTable::add_row(const std::vector<double>& values) {
  if (values.size() != columns_.size()) {
    throw std::invalid_argument("CSV row for " + path_ + " has " + std::to_string(values.size()) +
                                " values for " + std::to_string(columns_.size()) + " columns");
  }
  rows_.push_back(values);
}

void CsvTable::flush() const {
  std::ostringstream out;
  out.imbue(std::locale::classic());
  out << std::setprecision(10);
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
  json_assign(entries_, is_object_, objects_, key,
              std::isfinite(value) ? format_number(value, 12) : "null", std::nullopt);
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

void write_dataset(hid_t file, const std::string& path, const std::string& name,
                   const std::vector<hsize_t>& dims, const double* data) {
  const std::string where = "dataset " + name + " in " + path;
  H5Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose,
                 "create the dataspace of " + where);
  H5Handle dataset(H5Dcreate2(file, name.c_str(), H5T_IEEE_F64LE, space.get(), H5P_DEFAULT,
                              H5P_DEFAULT, H5P_DEFAULT),
                   H5Dclose, "create " + where);
  if (dims.front() > 0 &&
      H5Dwrite(dataset.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0) {
    throw std::runtime_error("HDF5: cannot write " + where);
  }
  dataset.close("close " + where);
}

void write_snapshot_file(const std::string& path, double time,
                         const std::vector<double>& positions,
                         const std::vector<SnapshotField>& fields) {
  const auto n = static_cast<hsize_t>(positions.size() / 3);
  H5Handle file(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose,
                "create " + path);
  write_dataset(file.get(), path, "position", {n, 3}, positions.data());
  for (const auto& field : fields) {
    std::vector<hsize_t> dims{n};
    if (field.components > 1) dims.push_back(static_cast<hsize_t>(field.components));
    write_dataset(file.get(), path, field.name, dims, field.data.data());
  }
  H5Handle scalar(H5Screate(H5S_SCALAR), H5Sclose, "create a scalar dataspace");
  H5Handle attribute(
      H5Acreate2(file.get(), "time", H5T_IEEE_F64LE, scalar.get(), H5P_DEFAULT, H5P_DEFAULT),
      H5Aclose, "create attribute time in " + path);
  if (H5Awrite(attribute.get(), H5T_NATIVE_DOUBLE, &time) < 0) {
    throw std::runtime_error("HDF5: cannot write attribute time in " + path);
  }
  attribute.close("close attribute time in " + path);
  file.close("close " + path);
}

std::string xml_escape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string hdf_data_item(const std::string& dimensions, const std::string& file,
                          const std::string& dataset) {
  return "<DataItem Format=\"HDF\" NumberType=\"Float\" Precision=\"8\" Dimensions=\"" +
         dimensions + "\">" + xml_escape(file + ":/" + dataset) + "</DataItem>";
}

}  // namespace
#endif

SnapshotWriter::SnapshotWriter(std::string dir, int dimension)
    : dir_(std::move(dir)), dimension_(dimension) {
  if (dimension_ != 2 && dimension_ != 3) {
    throw std::invalid_argument("SnapshotWriter: dimension must be 2 or 3, not " +
                                std::to_string(dimension_));
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
void SnapshotWriter::write(double time, const std::vector<std::array<double, 3>>& positions,
                           const std::vector<SnapshotField>& fields) {
  if (dir_.empty()) throw std::logic_error("SnapshotWriter::write: no output directory");
  const std::size_t n = positions.size();
  std::vector<std::pair<std::string, int>> layout;
  for (const auto& field : fields) {
    if (field.name.empty() || field.name == "." || field.name == "position" ||
        field.name.find('/') != std::string::npos) {
      throw std::invalid_argument("snapshot field name '" + field.name + "' is not allowed");
    }
    if (std::any_of(layout.begin(), layout.end(),
                    [&](const auto& entry) { return entry.first == field.name; })) {
      throw std::invalid_argument("snapshot field '" + field.name + "' is given twice");
    }
    if (field.components < 1 || field.data.size() != n * field.components) {
      throw std::invalid_argument("snapshot field '" + field.name + "' has " +
                                  std::to_string(field.data.size()) + " values for " +
                                  std::to_string(n) + " particles x " +
                                  std::to_string(field.components) + " components");
    }
    layout.emplace_back(field.name, field.components);
  }

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
    write_snapshot_file(tmp, time, flat, fields);
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
  rename_into_place(tmp, path);

  times_.push_back(time);
  files_.push_back(name);
  layouts_.push_back(std::move(layout));
  sizes_.push_back(static_cast<long long>(n));

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
    xmf += "    <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" + points +
           "\" NodesPerElement=\"1\"/>\n";
    xmf += "    <Geometry GeometryType=\"XYZ\">\n";
    xmf += "     " + hdf_data_item(points + " 3", files_[s], "position") + "\n";
    xmf += "    </Geometry>\n";
    for (const auto& [field, components] : layouts_[s]) {
      const char* type = components == 1 ? "Scalar" : components == 3 ? "Vector" : "Matrix";
      const std::string dims =
          components == 1 ? points : points + " " + std::to_string(components);
      xmf += "    <Attribute Name=\"" + xml_escape(field) + "\" AttributeType=\"" + type +
             "\" Center=\"Node\">\n";
      xmf += "     " + hdf_data_item(dims, files_[s], field) + "\n";
      xmf += "    </Attribute>\n";
    }
    xmf += "   </Grid>\n";
  }
  xmf +=
      "  </Grid>\n"
      " </Domain>\n"
      "</Xdmf>\n";
  write_file_atomically((snapshots / "snapshots.xmf").string(), xmf);
}
#else
void SnapshotWriter::write(double, const std::vector<std::array<double, 3>>&,
                           const std::vector<SnapshotField>&) {}
#endif

}  // namespace isph
