#pragma once
// The file of a captured pressure Poisson system (docs/SOLVERS.md, "Captured PPEs"), written by
// isph_ppe_capture and read by isph_ppe_bench --matrix. Layout (little-endian): "ISPHPPE1", int64 rows,
// int64 nonzeros, int64 dimension, int32 row_offset[rows + 1], int32 col[nonzeros], float64
// val[nonzeros], float64 rhs[rows], float64 start[rows], uint8 kind[rows] (FluidKind), uint8
// class[rows] (SurfaceClass).
#include <cstdint>
#include <fstream>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "poisson/linear_solver.hpp"

namespace isph::bench {

inline constexpr char kCapturedPpeMagic[] = "ISPHPPE1";

struct CapturedPpe {
  int dimension = 2;
  CsrMatrix A;
  std::vector<double> b, start;             // the right-hand side and the solve's start
  std::vector<std::uint8_t> kind, surface;  // each row's particle kind and surface class
};

inline void write_captured_ppe(const std::string& path, int dimension, const CsrMatrix& A, std::span<const double> b,
                               std::span<const double> start, std::span<const std::uint8_t> kind,
                               std::span<const std::uint8_t> surface) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw std::runtime_error("cannot write " + path);
  const std::int64_t header[3] = {A.rows, A.row_offset[A.rows], dimension};
  const auto put = [&out](const auto* data, std::size_t count) {
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(sizeof(*data) * count));
  };
  out.write(kCapturedPpeMagic, 8);
  put(header, 3);
  put(A.row_offset.data(), A.rows + 1);
  put(A.col.data(), header[1]);
  put(A.val.data(), header[1]);
  for (const auto& rows : {b, start}) put(rows.data(), rows.size());
  for (const auto& rows : {kind, surface}) put(rows.data(), rows.size());
  if (!out) throw std::runtime_error("writing " + path + " failed");
}

inline CapturedPpe read_captured_ppe(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[8] = {};
  std::int64_t header[3] = {};  // rows, nonzeros, dimension
  in.read(magic, 8);
  in.read(reinterpret_cast<char*>(header), sizeof header);
  const auto [rows, nonzeros, dimension] = header;
  if (!in || std::string(magic, 8) != kCapturedPpeMagic || rows <= 0 || nonzeros < rows || dimension < 2 ||
      dimension > 3)
    throw std::runtime_error(path + " is not a system written by isph_ppe_capture");
  CapturedPpe s;
  s.dimension = static_cast<int>(dimension);
  s.A.rows = static_cast<int>(rows);
  s.A.row_offset.resize(rows + 1);
  s.A.col.resize(nonzeros);
  s.A.val.resize(nonzeros);
  for (auto* v : {&s.b, &s.start}) v->resize(rows);
  for (auto* v : {&s.kind, &s.surface}) v->resize(rows);
  const auto get = [&in](auto& v) { in.read(reinterpret_cast<char*>(v.data()), sizeof(v[0]) * v.size()); };
  get(s.A.row_offset);
  get(s.A.col);
  get(s.A.val);
  get(s.b);
  get(s.start);
  get(s.kind);
  get(s.surface);
  if (!in) throw std::runtime_error(path + " ends early");
  return s;
}

}  // namespace isph::bench
