// The cuda backend on the debug device (core/device_emulation.hpp): the project's BiCGSTAB and AMG
// (poisson/krylov.hpp) over device arrays, every vector loop a launch on the cuda device, as in the
// cuda backend. cuSPARSE and cuBLAS have no host stand-in, so the product and the dot products are the
// launcher's: CsrRowProduct per row and ordered_sum of ProductAt. The iterates therefore differ from
// the GPU's in the last bits, not in the path they take through the code.
#include <memory>

#include "core/ordered_sum.hpp"
#include "poisson/device_array_ops.hpp"
#include "poisson/krylov.hpp"

namespace isph::detail {

namespace {

class DebugDeviceOps : public DeviceArrayOps {
 public:
  void set_matrix(const CsrMatrix& A) {
    rows_ = A.rows;
    row_offset_.assign(A.row_offset);
    col_.assign(A.col);
    val_.assign(A.val);
  }
  CsrView matrix() const { return {rows_, row_offset_.data(), col_.data(), val_.data()}; }
  void spmv(const Vector& x, Vector& y) const {
    parallel_for(
        exec(), rows_,
        CsrRowProduct{
            .row_offset = row_offset_.data(), .col = col_.data(), .val = val_.data(), .x = x.data(), .y = y.data()});
  }
  double dot(const Vector& x, const Vector& y) {
    return ordered_sum(exec(), static_cast<Index>(x.size()), ProductAt{x.data(), y.data()}, partial_sums_);
  }
  void release() {}  // the arrays stay for the next matrix

 private:
  int rows_ = 0;
  DeviceArray<int> row_offset_, col_;
  DeviceArray<double> val_;
  StateVector<double> partial_sums_{StateAllocator<double>(true)};
};

}  // namespace

std::unique_ptr<LinearSolver> make_debug_device_solver(const SolverSettings& s) {
  return std::make_unique<OwnKrylovSolver<DebugDeviceOps>>(s);
}

}  // namespace isph::detail
