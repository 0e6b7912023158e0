#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "io/output.hpp"

#ifdef ISPH_HAVE_HDF5
#include <hdf5.h>
#endif

namespace fs = std::filesystem;
using namespace isph;

namespace {

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

std::size_t count_occurrences(const std::string& text, const std::string& needle) {
  std::size_t n = 0;
  for (auto at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) ++n;
  return n;
}

// A fresh directory per test, removed afterwards.
class OutputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("isph_test_output_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

#ifdef ISPH_HAVE_HDF5
// True when every element opened in `xml` is closed in order (processing instructions,
// declarations and self-closing tags aside). Not a full XML parser.
bool tags_balanced(const std::string& xml) {
  std::vector<std::string> open;
  for (auto start = xml.find('<'); start != std::string::npos; start = xml.find('<', start + 1)) {
    const auto end = xml.find('>', start);
    if (end == std::string::npos) return false;
    const std::string tag = xml.substr(start + 1, end - start - 1);
    if (tag.empty() || tag[0] == '?' || tag[0] == '!' || tag.back() == '/') continue;
    if (tag[0] == '/') {
      if (open.empty() || open.back() != tag.substr(1)) return false;
      open.pop_back();
    } else {
      open.push_back(tag.substr(0, tag.find(' ')));
    }
  }
  return open.empty();
}

struct Dataset {
  std::vector<hsize_t> dims;
  std::vector<double> values;
};

Dataset read_dataset(const fs::path& file_path, const std::string& name) {
  Dataset result;
  const hid_t file = H5Fopen(file_path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) throw std::runtime_error("cannot open " + file_path.string());
  const bool exists = H5Lexists(file, name.c_str(), H5P_DEFAULT) > 0;
  const hid_t dataset = exists ? H5Dopen2(file, name.c_str(), H5P_DEFAULT) : -1;
  if (dataset >= 0) {
    const hid_t space = H5Dget_space(dataset);
    result.dims.resize(static_cast<std::size_t>(H5Sget_simple_extent_ndims(space)));
    H5Sget_simple_extent_dims(space, result.dims.data(), nullptr);
    result.values.resize(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
    H5Dread(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, result.values.data());
    H5Sclose(space);
    H5Dclose(dataset);
  }
  H5Fclose(file);
  if (dataset < 0) throw std::runtime_error("no dataset " + name + " in " + file_path.string());
  return result;
}

double read_time(const fs::path& file_path) {
  const hid_t file = H5Fopen(file_path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) throw std::runtime_error("cannot open " + file_path.string());
  double time = std::numeric_limits<double>::quiet_NaN();
  const hid_t attribute = H5Aopen(file, "time", H5P_DEFAULT);
  if (attribute >= 0) {
    H5Aread(attribute, H5T_NATIVE_DOUBLE, &time);
    H5Aclose(attribute);
  }
  H5Fclose(file);
  return time;
}
#endif

}  // namespace

TEST_F(OutputTest, WriteFileAtomicallyReplacesContentAndLeavesNoTemporary) {
  const fs::path path = dir_ / "a.txt";
  write_file_atomically(path.string(), "first\n");
  write_file_atomically(path.string(), "second\n");
  EXPECT_EQ(read_text(path), "second\n");
  EXPECT_FALSE(fs::exists(path.string() + ".tmp"));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
}

TEST_F(OutputTest, WriteFileAtomicallyNamesThePathOnFailure) {
  const std::string path = (dir_ / "missing" / "a.txt").string();
  try {
    write_file_atomically(path, "x");
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("No such file or directory"), std::string::npos) << e.what();
  }
}

TEST_F(OutputTest, CsvTableWritesHeaderAndRows) {
  const fs::path path = dir_ / "probes.csv";
  CsvTable table(path.string(), {"time", "tip.uy", "third"});
  table.add_row({0.0, 1.5, 1.0 / 3.0});
  table.add_row({0.1, -2e-7, 123456789012.0});
  EXPECT_EQ(table.rows(), 2u);
  table.flush();
  EXPECT_EQ(read_text(path),
            "time,tip.uy,third\n"
            "0,1.5,0.3333333333\n"
            "0.1,-2e-07,1.23456789e+11\n");
  EXPECT_FALSE(fs::exists(path.string() + ".tmp"));

  table.add_row({0.2, 0.0, 0.0});
  table.flush();
  EXPECT_EQ(count_occurrences(read_text(path), "\n"), 4u);
}

TEST_F(OutputTest, CsvTableRejectsRowsOfTheWrongSize) {
  CsvTable table((dir_ / "t.csv").string(), {"a", "b"});
  EXPECT_THROW(table.add_row({1.0}), std::invalid_argument);
  EXPECT_THROW(table.add_row({1.0, 2.0, 3.0}), std::invalid_argument);
  EXPECT_EQ(table.rows(), 0u);
  EXPECT_THROW(CsvTable((dir_ / "u.csv").string(), {"a,b"}), std::invalid_argument);
}

TEST(JsonObject, EscapesStrings) {
  JsonObject json;
  json.set("text", std::string("quote\" backslash\\ newline\n tab\t bell\x07 é"));
  json.set("key \"q\"", "v");
  EXPECT_EQ(json.dump(0),
            "{\"text\":\"quote\\\" backslash\\\\ newline\\n tab\\t bell\\u0007 é\","
            "\"key \\\"q\\\"\":\"v\"}");
}

TEST(JsonObject, WritesNumbersBooleansAndNonFiniteAsNull) {
  JsonObject json;
  json.set("pi", 3.14159265358979)
      .set("third", 1.0 / 3.0)
      .set("big", 1e300)
      .set("nan", std::numeric_limits<double>::quiet_NaN())
      .set("inf", -std::numeric_limits<double>::infinity())
      .set("steps", 9007199254740993LL)
      .set("count", 3)
      .set("converged", true)
      .set("failed", false);
  EXPECT_EQ(json.dump(0),
            "{\"pi\":3.14159265359,\"third\":0.333333333333,\"big\":1e+300,\"nan\":null,"
            "\"inf\":null,\"steps\":9007199254740993,\"count\":3,\"converged\":true,"
            "\"failed\":false}");
}

TEST(JsonObject, NestsAndPrettyPrintsInInsertionOrder) {
  JsonObject inner;
  inner.set("b", 2).set("a", 1);
  JsonObject json;
  json.set("z", "first").set("inner", inner).set("empty", JsonObject()).set("last", 0.5);
  EXPECT_EQ(json.dump(),
            "{\n"
            "  \"z\": \"first\",\n"
            "  \"inner\": {\n"
            "    \"b\": 2,\n"
            "    \"a\": 1\n"
            "  },\n"
            "  \"empty\": {},\n"
            "  \"last\": 0.5\n"
            "}");
  EXPECT_EQ(JsonObject().dump(), "{}");
}

TEST(JsonObject, SettingAKeyAgainReplacesItInPlace) {
  JsonObject inner;
  inner.set("x", 1);
  JsonObject json;
  json.set("a", 1).set("b", inner).set("c", inner);
  json.set("a", inner).set("b", "text").set("c", 2);
  EXPECT_EQ(json.dump(0), "{\"a\":{\"x\":1},\"b\":\"text\",\"c\":2}");
  json.set("self", json);
  EXPECT_EQ(json.dump(0),
            "{\"a\":{\"x\":1},\"b\":\"text\",\"c\":2,"
            "\"self\":{\"a\":{\"x\":1},\"b\":\"text\",\"c\":2}}");
}

TEST_F(OutputTest, SnapshotWriterWithoutHdf5DoesNothing) {
  if (SnapshotWriter::available()) GTEST_SKIP() << "built with HDF5";
  SnapshotWriter writer(dir_.string(), 2);
  writer.write(0.0, {{0.0, 0.0, 0.0}}, {});
  EXPECT_FALSE(fs::exists(dir_ / "snapshots"));
}

TEST_F(OutputTest, SnapshotWriterWritesHdf5FilesAndXdmfIndex) {
#ifndef ISPH_HAVE_HDF5
  GTEST_SKIP() << "built without HDF5";
#else
  ASSERT_TRUE(SnapshotWriter::available());
  SnapshotWriter writer(dir_.string(), 2);
  const std::vector<std::array<double, 3>> positions{{0.0, 1.0, 7.0}, {2.5, -3.0, 7.0}};
  writer.write(0.0, positions, {{"pressure", 1, {10.0, 20.0}}, {"velocity", 3, {1, 2, 0, 3, 4, 0}}});
  writer.write(0.25, positions,
               {{"pressure", 1, {11.0, 21.0}}, {"stress", 4, {1, 2, 3, 4, 5, 6, 7, 8}}, {"kind", 1, {0.0, 2.0}}});
  EXPECT_EQ(writer.count(), 2);

  const fs::path snapshots = dir_ / "snapshots";
  const fs::path first = snapshots / "snapshot_00000.h5";
  const fs::path second = snapshots / "snapshot_00001.h5";
  const Dataset position = read_dataset(first, "position");
  EXPECT_EQ(position.dims, (std::vector<hsize_t>{2, 3}));
  EXPECT_EQ(position.values, (std::vector<double>{0.0, 1.0, 0.0, 2.5, -3.0, 0.0}));  // z = 0 in 2D
  const Dataset velocity = read_dataset(first, "velocity");
  EXPECT_EQ(velocity.dims, (std::vector<hsize_t>{2, 3}));
  EXPECT_EQ(velocity.values, (std::vector<double>{1, 2, 0, 3, 4, 0}));
  const Dataset pressure = read_dataset(second, "pressure");
  EXPECT_EQ(pressure.dims, (std::vector<hsize_t>{2}));
  EXPECT_EQ(pressure.values, (std::vector<double>{11.0, 21.0}));
  EXPECT_EQ(read_dataset(second, "stress").dims, (std::vector<hsize_t>{2, 4}));
  EXPECT_THROW(read_dataset(second, "velocity"), std::runtime_error);
  EXPECT_EQ(read_time(first), 0.0);
  EXPECT_EQ(read_time(second), 0.25);

  for (const auto& entry : fs::directory_iterator(snapshots)) {
    EXPECT_NE(entry.path().extension(), ".tmp") << entry.path();
  }

  const std::string xmf = read_text(snapshots / "snapshots.xmf");
  EXPECT_TRUE(tags_balanced(xmf)) << xmf;
  EXPECT_EQ(count_occurrences(xmf, "CollectionType=\"Temporal\""), 1u);
  EXPECT_EQ(count_occurrences(xmf, "GridType=\"Uniform\""), 2u);
  EXPECT_NE(xmf.find("<Time Value=\"0\"/>"), std::string::npos);
  EXPECT_NE(xmf.find("<Time Value=\"0.25\"/>"), std::string::npos);
  EXPECT_NE(xmf.find(">snapshot_00000.h5:/position<"), std::string::npos);
  EXPECT_NE(xmf.find(">snapshot_00001.h5:/position<"), std::string::npos);
  EXPECT_NE(xmf.find("Dimensions=\"2 3\">snapshot_00000.h5:/velocity<"), std::string::npos);
  EXPECT_NE(xmf.find("Dimensions=\"2 4\">snapshot_00001.h5:/stress<"), std::string::npos);
  EXPECT_NE(xmf.find("Dimensions=\"2\">snapshot_00001.h5:/kind<"), std::string::npos);
  EXPECT_EQ(count_occurrences(xmf, "AttributeType=\"Scalar\""), 3u);
  EXPECT_EQ(count_occurrences(xmf, "AttributeType=\"Vector\""), 1u);
  EXPECT_EQ(count_occurrences(xmf, "AttributeType=\"Matrix\""), 1u);
  EXPECT_EQ(count_occurrences(xmf, "NumberOfElements=\"2\""), 2u);
#endif
}

TEST_F(OutputTest, SnapshotWriterRejectsInconsistentFields) {
#ifndef ISPH_HAVE_HDF5
  GTEST_SKIP() << "built without HDF5";
#else
  SnapshotWriter writer(dir_.string(), 3);
  const std::vector<std::array<double, 3>> positions{{0, 0, 0}, {1, 1, 1}};
  EXPECT_THROW(writer.write(0.0, positions, {{"p", 1, {1.0}}}), std::invalid_argument);
  EXPECT_THROW(writer.write(0.0, positions, {{"v", 3, {1, 2, 3, 4, 5}}}), std::invalid_argument);
  EXPECT_THROW(writer.write(0.0, positions, {{"p", 1, {1, 2}}, {"p", 1, {1, 2}}}), std::invalid_argument);
  EXPECT_THROW(writer.write(0.0, positions, {{"position", 1, {1, 2}}}), std::invalid_argument);
  EXPECT_THROW(writer.write(0.0, positions, {{"a/b", 1, {1, 2}}}), std::invalid_argument);
  EXPECT_EQ(writer.count(), 0);
#endif
}

TEST_F(OutputTest, SnapshotReadsBackWhatWasWritten) {
#ifndef ISPH_HAVE_HDF5
  GTEST_SKIP() << "built without HDF5";
#else
  SnapshotWriter writer(dir_.string(), 2);
  const std::vector<std::array<double, 3>> positions{{0.5, 1.0, 0.0}, {2.5, -3.0, 0.0}, {1, 1, 0}};
  writer.write(0.125, positions, {{"id", 1, {2, 0, 1}}, {"velocity", 3, {1, 2, 0, 3, 4, 0, 5, 6, 0}}},
               {{"wall_work", -1.5}, {"interaction_work", 3.25}});
  const SnapshotData s = read_snapshot((dir_ / "snapshots" / "snapshot_00000.h5").string());
  EXPECT_EQ(s.time, 0.125);
  EXPECT_EQ(s.attributes.at("wall_work"), -1.5);
  EXPECT_EQ(s.attributes.at("interaction_work"), 3.25);
  EXPECT_EQ(s.size(), 3u);
  EXPECT_EQ(s.field("position").components, 3);
  EXPECT_EQ(s.field("position").data, (std::vector<double>{0.5, 1.0, 0.0, 2.5, -3.0, 0.0, 1, 1, 0}));
  EXPECT_EQ(s.field("velocity").data, (std::vector<double>{1, 2, 0, 3, 4, 0, 5, 6, 0}));
  EXPECT_EQ(s.field("id").components, 1);
  EXPECT_EQ(s.rows_by_id(), (std::vector<long long>{1, 2, 0}));
  EXPECT_THROW(s.field("pressure"), std::runtime_error);
  EXPECT_THROW(read_snapshot((dir_ / "snapshots" / "snapshot_00001.h5").string()), std::runtime_error);
  std::ofstream(dir_ / "not_hdf5.h5") << "text";
  EXPECT_THROW(read_snapshot((dir_ / "not_hdf5.h5").string()), std::runtime_error);
#endif
}

// A restart from a run's folder takes its newest snapshot that reads back: one cut short or damaged
// (here a text file under a snapshot's name) is passed over, and so are names of other files.
TEST_F(OutputTest, NewestSnapshotPassesOverOneThatDoesNotReadBack) {
#ifndef ISPH_HAVE_HDF5
  GTEST_SKIP() << "built without HDF5";
#else
  SnapshotWriter writer(dir_.string(), 2);
  const std::vector<std::array<double, 3>> positions{{0.5, 1.0, 0.0}};
  for (double t : {0.0, 0.5}) writer.write(t, positions, {{"id", 1, {0}}});
  const fs::path snapshots = dir_ / "snapshots";
  EXPECT_EQ(newest_snapshot(dir_.string()), (snapshots / "snapshot_00001.h5").string());
  std::ofstream(snapshots / "snapshot_00002.h5") << "cut short";
  std::ofstream(snapshots / "snapshot_00003.h5.tmp") << "cut short";
  std::ofstream(snapshots / "snapshot_x.h5") << "not a snapshot's name";
  EXPECT_EQ(newest_snapshot(dir_.string()), (snapshots / "snapshot_00001.h5").string());
  EXPECT_EQ(newest_snapshot(snapshots.string()), (snapshots / "snapshot_00001.h5").string());
  const fs::path empty = dir_ / "empty";
  fs::create_directories(empty);
  EXPECT_THROW(newest_snapshot(empty.string()), std::runtime_error);
#endif
}

TEST_F(OutputTest, CsvTableCarriesTheRowsBeforeATime) {
  const fs::path earlier = dir_ / "earlier.csv";
  std::ofstream(earlier) << "time,a\n0,1\n0.5,2\n1,3\n1.5,4\n";
  CsvTable table((dir_ / "later.csv").string(), {"time", "a"});
  EXPECT_EQ(table.add_rows_before(earlier.string(), 1.0), 2u);
  table.add_row({1.0, 30});
  table.flush();
  EXPECT_EQ(read_text(dir_ / "later.csv"), "time,a\n0,1\n0.5,2\n1,30\n");
  CsvTable other((dir_ / "other.csv").string(), {"time", "b"});
  EXPECT_THROW(other.add_rows_before(earlier.string(), 1.0), std::runtime_error);
  std::ofstream(dir_ / "broken.csv") << "time,a\n0,x\n";
  EXPECT_THROW(table.add_rows_before((dir_ / "broken.csv").string(), 1.0), std::runtime_error);
  EXPECT_THROW(table.add_rows_before((dir_ / "missing.csv").string(), 1.0), std::runtime_error);
}
