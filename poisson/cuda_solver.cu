// The cuda backend: the project's BiCGSTAB (poisson/krylov.hpp) on the GPU. The matrix and every vector
// stay in device memory during a solve; SpMV is cuSPARSE's generic CSR product (or, for the benchmark,
// the project's vector CSR kernel), dot products are
// cuBLAS's, and the vector updates are the launcher functors that the native backend runs on the host.
// Only b, x and the scalars of the recurrences cross the bus.
#include <cublas_v2.h>
#include <cuda_runtime.h>
#include <cusparse.h>

#include <algorithm>
#include <limits>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/device_memory.hpp"
#include "poisson/cuda_solver.hpp"
#include "poisson/device_array_ops.hpp"
#include "poisson/krylov.hpp"

namespace isph {
namespace {

void check(cusparseStatus_t s, const char* what) {
  if (s != CUSPARSE_STATUS_SUCCESS)
    throw std::runtime_error(std::string("cuSPARSE ") + what + ": " + cusparseGetErrorString(s));
}
void check(cublasStatus_t s, const char* what) {
  if (s != CUBLAS_STATUS_SUCCESS)
    throw std::runtime_error(std::string("cuBLAS ") + what + ": " + cublasGetStatusString(s));
}
void check(cudaError_t s, const char* what) {
  if (s != cudaSuccess) throw std::runtime_error(std::string(what) + ": " + cudaGetErrorString(s));
}

void require_device(const char* who) {
  if (cuda_devices() == 0)
    throw std::runtime_error(std::string(who) + " needs a CUDA device, and none is visible to this process");
}

// The solver uses CSR_ALG2, which gives bit-wise reproducible products (cuSPARSE documentation), so
// that repeated runs agree; the benchmark also times CSR_ALG1, the default, and the vector CSR kernel.
cusparseSpMVAlg_t spmv_algorithm(SpmvAlgorithm a) {
  return a == SpmvAlgorithm::reproducible ? CUSPARSE_SPMV_CSR_ALG2 : CUSPARSE_SPMV_CSR_ALG1;
}

// y = A x with Lanes threads per row, the "vector CSR" product of Bell & Garland (2009, Implementing
// sparse matrix-vector multiplication on throughput-oriented processors): the lanes of a row read its
// entries side by side, so that the loads of col and val coalesce; lane l sums entries l, l + Lanes, ...
// of the row, and a shuffle tree adds the lanes' sums in a fixed order, so that a product gives the same
// bits on every run. Every thread of a warp reaches the shuffles (rows past the end add nothing).
template <int Lanes>
__global__ void vector_csr_product(int rows, const int* __restrict__ row_offset, const int* __restrict__ col,
                                   const double* __restrict__ val, const double* __restrict__ x,
                                   double* __restrict__ y) {
  const long long thread = static_cast<long long>(blockIdx.x) * blockDim.x + threadIdx.x;
  const long long row = thread / Lanes;
  const int lane = static_cast<int>(thread % Lanes);
  double s = 0;
  if (row < rows)
    for (int k = row_offset[row] + lane; k < row_offset[row + 1]; k += Lanes) s += val[k] * x[col[k]];
  for (int offset = Lanes / 2; offset > 0; offset /= 2) s += __shfl_down_sync(0xffffffffu, s, offset, Lanes);
  if (lane == 0 && row < rows) y[row] = s;
}

template <int Lanes>
void launch_vector_csr(int rows, const int* row_offset, const int* col, const double* val, const double* x, double* y) {
  constexpr int block = 256;
  const long long threads = static_cast<long long>(rows) * Lanes;
  const auto grid = static_cast<unsigned>((threads + block - 1) / block);
  vector_csr_product<Lanes><<<grid, block>>>(rows, row_offset, col, val, x, y);
  check(cudaGetLastError(), "vector CSR product");
}

void vector_csr(int lanes, int rows, const int* row_offset, const int* col, const double* val, const double* x,
                double* y) {
  if (rows == 0) return;
  switch (lanes) {
    case 2:
      return launch_vector_csr<2>(rows, row_offset, col, val, x, y);
    case 4:
      return launch_vector_csr<4>(rows, row_offset, col, val, x, y);
    case 8:
      return launch_vector_csr<8>(rows, row_offset, col, val, x, y);
    case 16:
      return launch_vector_csr<16>(rows, row_offset, col, val, x, y);
    case 32:
      return launch_vector_csr<32>(rows, row_offset, col, val, x, y);
    default:
      throw std::invalid_argument("vector CSR product: " + std::to_string(lanes) +
                                  " lanes per row (2, 4, 8, 16 or 32)");
  }
}

class CudaOps : public DeviceArrayOps {
 public:
  // lanes: the vector CSR kernel's threads per row; 0 chooses them from each matrix (vector_csr_lanes).
  explicit CudaOps(SpmvAlgorithm algorithm = SpmvAlgorithm::reproducible, int lanes = 0)
      : vector_csr_(algorithm == SpmvAlgorithm::vector_csr), lanes_(lanes), algorithm_(spmv_algorithm(algorithm)) {
    check(cusparseCreate(&sparse_), "create");
    check(cublasCreate(&blas_), "create");
  }
  ~CudaOps() {
    release();
    cublasDestroy(blas_);
    cusparseDestroy(sparse_);
  }
  CudaOps(const CudaOps&) = delete;
  CudaOps& operator=(const CudaOps&) = delete;

  // The device arrays are reused from matrix to matrix (reallocated only when a size changes); the
  // descriptors, host-side objects, are made anew.
  void set_matrix(const CsrMatrix& A) {
    release();
    rows_ = A.rows;
    row_offset_.assign(A.row_offset);
    col_.assign(A.col);
    val_.assign(A.val);
    if (vector_csr_) {
      matrix_lanes_ = lanes_ > 0 ? lanes_ : vector_csr_lanes(A.rows > 0 ? double(A.val.size()) / A.rows : 0.0);
      return;
    }
    scratch_.grow_to(static_cast<std::size_t>(A.rows));
    check(
        cusparseCreateCsr(&matrix_, A.rows, A.rows, static_cast<int64_t>(A.val.size()), row_offset_.data(), col_.data(),
                          val_.data(), CUSPARSE_INDEX_32I, CUSPARSE_INDEX_32I, CUSPARSE_INDEX_BASE_ZERO, CUDA_R_64F),
        "create CSR matrix");
    check(cusparseCreateDnVec(&x_, A.rows, scratch_.data(), CUDA_R_64F), "create vector");
    check(cusparseCreateDnVec(&y_, A.rows, scratch_.data(), CUDA_R_64F), "create vector");
    std::size_t bytes = 0;
    const double one = 1, zero = 0;
    check(cusparseSpMV_bufferSize(sparse_, CUSPARSE_OPERATION_NON_TRANSPOSE, &one, matrix_, x_, &zero, y_, CUDA_R_64F,
                                  algorithm_, &bytes),
          "SpMV buffer size");
    buffer_.grow_to(std::max<std::size_t>(bytes, 1));
    check(cusparseSpMV_preprocess(sparse_, CUSPARSE_OPERATION_NON_TRANSPOSE, &one, matrix_, x_, &zero, y_, CUDA_R_64F,
                                  algorithm_, buffer_.data()),
          "SpMV preprocess");
  }

  CsrView matrix() const { return {rows_, row_offset_.data(), col_.data(), val_.data()}; }

  void spmv(const Vector& x, Vector& y) {
    if (vector_csr_) {
      vector_csr(matrix_lanes_, rows_, row_offset_.data(), col_.data(), val_.data(), x.data(), y.data());
      return;
    }
    check(cusparseDnVecSetValues(x_, const_cast<double*>(x.data())), "set vector");
    check(cusparseDnVecSetValues(y_, y.data()), "set vector");
    const double one = 1, zero = 0;
    check(cusparseSpMV(sparse_, CUSPARSE_OPERATION_NON_TRANSPOSE, &one, matrix_, x_, &zero, y_, CUDA_R_64F, algorithm_,
                       buffer_.data()),
          "SpMV");
  }

  double dot(const Vector& x, const Vector& y) {
    double r = 0;
    check(cublasDdot(blas_, rows_, x.data(), 1, y.data(), 1, &r), "ddot");
    return r;
  }

  // Destroys the descriptors; the device arrays stay for the next matrix (and go with the object).
  void release() {
    if (x_) cusparseDestroyDnVec(x_);
    if (y_) cusparseDestroyDnVec(y_);
    if (matrix_) cusparseDestroySpMat(matrix_);
    x_ = y_ = nullptr;
    matrix_ = nullptr;
  }

 private:
  bool vector_csr_;  // the vector CSR kernel instead of cuSPARSE
  int lanes_, matrix_lanes_ = 2;
  cusparseSpMVAlg_t algorithm_;
  cusparseHandle_t sparse_ = nullptr;
  cublasHandle_t blas_ = nullptr;
  int rows_ = 0;
  DeviceArray<int> row_offset_, col_;
  DeviceArray<double> val_, scratch_;
  DeviceArray<unsigned char> buffer_;
  cusparseSpMatDescr_t matrix_ = nullptr;
  cusparseDnVecDescr_t x_ = nullptr, y_ = nullptr;
};

// Milliseconds between two events recorded around f().
template <class F>
double timed_ms(F&& f) {
  cudaEvent_t start, stop;
  check(cudaEventCreate(&start), "event");
  check(cudaEventCreate(&stop), "event");
  check(cudaEventRecord(start), "event");
  f();
  check(cudaEventRecord(stop), "event");
  check(cudaEventSynchronize(stop), "event");
  float ms = 0;
  check(cudaEventElapsedTime(&ms, start, stop), "event");
  cudaEventDestroy(start);
  cudaEventDestroy(stop);
  return ms;
}

}  // namespace

namespace detail {
std::unique_ptr<LinearSolver> make_cuda_solver(const SolverSettings& s) {
  if (cuda_devices() == 0)
    throw std::invalid_argument(
        "linear solver: backend 'cuda' needs a CUDA device, and none is visible to this process");
  return std::make_unique<OwnKrylovSolver<CudaOps>>(s);
}
}  // namespace detail

SpmvMeasurement measure_cuda_spmv(const CsrMatrix& A, const std::vector<double>& x, int repeats,
                                  SpmvAlgorithm algorithm, int lanes) {
  require_device("measure_cuda_spmv");
  check_linear_system(A, x, x);
  CudaOps ops(algorithm, lanes);
  ops.set_matrix(A);
  auto dx = ops.vector(A.rows), dy = ops.vector(A.rows);
  ops.upload(x, dx);
  ops.upload(std::vector<double>(A.rows, std::numeric_limits<double>::quiet_NaN()), dy);  // poisoned
  ops.spmv(dx, dy);                                                                       // warm-up
  SpmvMeasurement m;
  m.seconds_per_product = 1e-3 * timed_ms([&] {
                            for (int k = 0; k < repeats; ++k) ops.spmv(dx, dy);
                          }) /
                          repeats;
  dy.download(m.y);  // resizes m.y
  m.bytes_per_product = 12.0 * A.val.size() + 4.0 * (A.rows + 1) + 16.0 * A.rows;

  constexpr std::size_t copy_bytes = std::size_t{512} << 20;
  DeviceArray<unsigned char> from(copy_bytes), to(copy_bytes);
  const auto copy = [&] { check(cudaMemcpy(to.data(), from.data(), copy_bytes, cudaMemcpyDeviceToDevice), "copy"); };
  copy();  // warm-up
  constexpr int copies = 10;
  const double ms = timed_ms([&] {
    for (int k = 0; k < copies; ++k) copy();
  });
  m.copy_bandwidth = 2.0 * copy_bytes * copies / (1e-3 * ms);
  return m;
}

}  // namespace isph
