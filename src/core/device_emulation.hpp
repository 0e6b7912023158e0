#pragma once
// The debug device (`isph run --device debug`): the cuda device's code path, run on the CPU. Every
// branch that the cuda device takes is taken (managed and device arrays, the device neighbour list,
// queued substeps, the PPE solved by the project's Krylov solver on device arrays), but each launch
// runs its functor on the host. It needs no GPU, so CI runs the GPU path's logic on every commit; it
// is slow, and it is for testing.
//
// Its device memory is one reserved range of the address space, kept inaccessible to the host outside
// launches (mprotect). A host access between launches faults; the fault handler opens that page and
// counts it, and the next launch closes every page again. The count is the number of pages the host
// touched between launches: on a GPU each is a page of managed memory moved to the host and back, the
// cost the device path is built to avoid. summary.json reports it per phase (MFEM's "debug" device
// protects its device memory the same way). With ISPH_DEBUG_DEVICE_BACKTRACE=1 every touch also prints
// the host's call stack to stderr (addresses in the binary: addr2line -Cfe build/isph names them).
#include <cstddef>

namespace isph {

// Whether the debug device is on: then cuda_devices() is 1, device allocations come from the range
// above, and launches on the cuda device run on the host. Switched on once, before any device array
// is made, and never off.
bool device_emulated();
void enable_device_emulation();

// Memory of the debug device: page-aligned, filled with 0xFF bytes, inaccessible to the host outside
// launches.
void* emulated_allocate(std::size_t bytes);
void emulated_free(void* p);
bool emulated_accessible(const void* p);  // inside the debug device's range (null counts, as on the GPU)

// Pages the host has touched between launches so far, and the launches so far.
long long emulated_host_touches();
long long emulated_launches();

// A launch on the debug device: its memory is open to the host while one exists (they nest).
class EmulatedLaunch {
 public:
  EmulatedLaunch();
  ~EmulatedLaunch();
  EmulatedLaunch(const EmulatedLaunch&) = delete;
  EmulatedLaunch& operator=(const EmulatedLaunch&) = delete;
};

}  // namespace isph
