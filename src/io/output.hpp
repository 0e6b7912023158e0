#pragma once
// Output files. Every file is written to a temporary name and renamed into place, so an
// interrupted run never leaves a truncated file.
#include <array>
#include <string>
#include <utility>
#include <vector>

namespace isph {

// Writes `content` to `path` through `path.tmp` and an atomic rename. Throws on failure.
void write_file_atomically(const std::string& path, const std::string& content);

// A CSV table kept in memory; flush() rewrites the whole file atomically.
class CsvTable {
 public:
  CsvTable() = default;
  CsvTable(std::string path, std::vector<std::string> columns);
  void add_row(const std::vector<double>& values);  // throws if the size differs from the columns
  void flush() const;
  std::size_t rows() const { return rows_.size(); }

 private:
  std::string path_;
  std::vector<std::string> columns_;
  std::vector<std::vector<double>> rows_;
};

// A minimal JSON object builder for summary.json (keys keep insertion order).
class JsonObject {
 public:
  JsonObject& set(const std::string& key, double value);
  JsonObject& set(const std::string& key, long long value);
  JsonObject& set(const std::string& key, int value) { return set(key, static_cast<long long>(value)); }
  JsonObject& set(const std::string& key, bool value);
  JsonObject& set(const std::string& key, const std::string& value);
  JsonObject& set(const std::string& key, const char* value) { return set(key, std::string(value)); }
  JsonObject& set(const std::string& key, const JsonObject& value);
  std::string dump(int indent = 2) const;

 private:
  std::vector<std::pair<std::string, std::string>> entries_;  // key, serialised value
  std::vector<bool> is_object_;
  std::vector<JsonObject> objects_;
  std::string dump_at(int indent, int level) const;
};

// One field of a snapshot: `components` values per particle (1 scalar, 3 vector), row-major.
struct SnapshotField {
  std::string name;
  int components = 1;
  std::vector<double> data;
};

// HDF5 snapshots plus one XDMF index (`snapshots.xmf`) that ParaView opens directly. Without HDF5
// (ISPH_HAVE_HDF5 undefined) available() is false and write() does nothing.
class SnapshotWriter {
 public:
  SnapshotWriter() = default;
  // dir: the output directory; snapshots go to dir/snapshots/.
  SnapshotWriter(std::string dir, int dimension);
  static bool available();
  // Writes dir/snapshots/snapshot_NNNNN.h5 with dataset "position" (N x 3, z = 0 in 2D) and one
  // dataset per field, then rewrites dir/snapshots/snapshots.xmf listing every snapshot so far.
  void write(double time, const std::vector<std::array<double, 3>>& positions,
             const std::vector<SnapshotField>& fields);
  int count() const { return static_cast<int>(times_.size()); }

 private:
  std::string dir_;
  int dimension_ = 2;
  std::vector<double> times_;
  std::vector<std::string> files_;
  std::vector<std::vector<std::pair<std::string, int>>> layouts_;  // field names and components
  std::vector<long long> sizes_;
};

}  // namespace isph
