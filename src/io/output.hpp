#pragma once
// Output files. Every file is written to a temporary name and renamed into place, so an
// interrupted run never leaves a truncated file.
#include <array>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace isph {

// Writes `content` to `path` through `path.tmp` and an atomic rename. Throws on failure.
void write_file_atomically(const std::string& path, const std::string& content);

// A CSV table kept in memory; flush() rewrites the whole file atomically.
class CsvTable {
 public:
  static constexpr int kDigits = 10;  // significant digits of every value written
  // The relative error of a written value: a time read back lies within this fraction of end_time.
  static constexpr double kRelativeResolution = 1e-9;
  CsvTable() = default;
  CsvTable(std::string path, std::vector<std::string> columns);
  void add_row(const std::vector<double>& values);  // throws if the size differs from the columns
  // Adds the rows of an earlier table at `path` whose first column (time) is below `before`: a
  // restarted run carries the history of the run it continues. Throws when the file cannot be read
  // or its header differs from this table's columns. Returns the rows added.
  std::size_t add_rows_before(const std::string& path, double before);
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

// Scalar attributes of a snapshot file besides its time (restart state such as accumulated work).
using SnapshotAttributes = std::vector<std::pair<std::string, double>>;

// HDF5 snapshots plus one XDMF index (`snapshots.xmf`) that ParaView opens directly. Without HDF5
// (ISPH_HAVE_HDF5 undefined) available() is false and write() does nothing.
class SnapshotWriter {
 public:
  SnapshotWriter() = default;
  // dir: the output directory; snapshots go to dir/snapshots/.
  SnapshotWriter(std::string dir, int dimension);
  static bool available();
  // Writes dir/snapshots/snapshot_NNNNN.h5 with dataset "position" (N x 3, z = 0 in 2D), one
  // dataset per field and the attributes "time" and `attributes`, then rewrites
  // dir/snapshots/snapshots.xmf listing every snapshot so far.
  void write(double time, const std::vector<std::array<double, 3>>& positions, const std::vector<SnapshotField>& fields,
             const SnapshotAttributes& attributes = {});
  int count() const { return static_cast<int>(times_.size()); }

 private:
  std::string xdmf_index() const;

  std::string dir_;
  int dimension_ = 2;
  std::vector<double> times_;
  std::vector<std::string> files_;
  std::vector<std::vector<std::pair<std::string, int>>> layouts_;  // field names and components
  std::vector<long long> sizes_;
};

// A snapshot file read back: its time, its scalar attributes (time included), and every dataset
// ("position" among them) as a field of 1 or 3 components per particle.
struct SnapshotData {
  double time = 0;
  std::map<std::string, double> attributes;
  std::map<std::string, SnapshotField> fields;
  std::size_t size() const;  // particles
  // The field `name`; throws naming the file when it is missing.
  const SnapshotField& field(const std::string& name) const;
  // The row of each stable id (the "id" field), -1 for ids the snapshot lacks.
  std::vector<long long> rows_by_id() const;
  std::string path;
};

// Reads a file written by SnapshotWriter. Throws std::runtime_error when it cannot be read, and
// when HDF5 is not built in.
SnapshotData read_snapshot(const std::string& path);

// The newest snapshot of a run folder (DIR/snapshots/snapshot_NNNNN.h5, or DIR itself holding them)
// that reads back whole: one that does not (a damaged file) is passed over, with a note on stderr.
// Throws std::runtime_error when there is none.
std::string newest_snapshot(const std::string& run_dir);

}  // namespace isph
