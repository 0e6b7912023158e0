#include "core/device_emulation.hpp"

#include <execinfo.h>
#include <signal.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace isph {

namespace {

// The debug device's memory: one range reserved at start (no memory behind it until touched), handed out
// in whole pages and never reused.
constexpr std::size_t kReservedBytes = std::size_t{256} << 30;

std::atomic<bool> emulated{false};
std::atomic<std::uintptr_t> range_base{0};
std::atomic<std::size_t> range_used{0};  // bytes handed out from the base (whole pages)
std::size_t page_bytes = 4096;
std::atomic<int> open_launches{0};
std::atomic<long long> host_touches{0}, launches{0};
std::mutex allocation_mutex;
std::unordered_map<const void*, std::size_t> allocation_bytes;  // for emulated_free
struct sigaction previous_handler {};
bool print_backtraces = false;  // ISPH_DEBUG_DEVICE_BACKTRACE=1: where each touch came from, on stderr

void set_access(int protection) {
  const std::size_t used = range_used.load();
  if (used > 0) mprotect(reinterpret_cast<void*>(range_base.load()), used, protection);
}

// A host access to a closed page of the range opens the page and is counted; any other fault goes to the
// handler that was there before (by default the process ends, as without this one).
void on_fault(int signal_number, siginfo_t* info, void* context) {
  const auto address = reinterpret_cast<std::uintptr_t>(info->si_addr);
  const std::uintptr_t base = range_base.load();
  if (address >= base && address < base + range_used.load()) {
    void* page = reinterpret_cast<void*>(address & ~(static_cast<std::uintptr_t>(page_bytes) - 1));
    // When the kernel cannot split the mapping once more (too many open pages), the whole range opens
    // until the next launch: the count is then a lower bound.
    if (mprotect(page, page_bytes, PROT_READ | PROT_WRITE) != 0) set_access(PROT_READ | PROT_WRITE);
    host_touches.fetch_add(1);
    if (print_backtraces) {
      void* frames[24];
      const int depth = backtrace(frames, 24);
      write(STDERR_FILENO, "debug device: host touch\n", 26);
      backtrace_symbols_fd(frames, depth, STDERR_FILENO);
    }
    return;
  }
  sigaction(SIGSEGV, &previous_handler, nullptr);
  if (!(previous_handler.sa_flags & SA_SIGINFO) && previous_handler.sa_handler != SIG_DFL &&
      previous_handler.sa_handler != SIG_IGN)
    previous_handler.sa_handler(signal_number);
  else if (previous_handler.sa_flags & SA_SIGINFO)
    previous_handler.sa_sigaction(signal_number, info, context);
  // With the default action restored, returning repeats the access, which now ends the process.
}

}  // namespace

bool device_emulated() { return emulated.load(std::memory_order_relaxed); }

void enable_device_emulation() {
  if (emulated.load()) return;
  page_bytes = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  void* base = mmap(nullptr, kReservedBytes, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
  if (base == MAP_FAILED) throw std::runtime_error("debug device: cannot reserve its address range");
  range_base = reinterpret_cast<std::uintptr_t>(base);
  const char* trace = std::getenv("ISPH_DEBUG_DEVICE_BACKTRACE");
  print_backtraces = trace && trace[0] == '1';
  if (print_backtraces) {  // loads what backtrace() needs now, not first inside the fault handler
    void* frame;
    backtrace(&frame, 1);
  }
  struct sigaction action {};
  action.sa_sigaction = on_fault;
  action.sa_flags = SA_SIGINFO;
  sigemptyset(&action.sa_mask);
  if (sigaction(SIGSEGV, &action, &previous_handler) != 0)
    throw std::runtime_error("debug device: cannot install its fault handler");
  emulated = true;
}

void* emulated_allocate(std::size_t bytes) {
  if (!device_emulated()) throw std::logic_error("emulated_allocate: the debug device is off");
  const std::size_t rounded = (std::max<std::size_t>(bytes, 1) + page_bytes - 1) / page_bytes * page_bytes;
  const std::lock_guard<std::mutex> lock(allocation_mutex);
  const std::size_t offset = range_used.load();
  if (offset + rounded > kReservedBytes)
    throw std::runtime_error("debug device: its " + std::to_string(kReservedBytes >> 30) + " GiB range is used up");
  void* p = reinterpret_cast<void*>(range_base.load() + offset);
  range_used = offset + rounded;
  // Filled with 0xFF bytes (NaN in a double, -1 in an integer), as cudaMalloc leaves memory unset: an
  // element read before it is written shows. The fill is the copy engine's, not a host touch.
  mprotect(p, rounded, PROT_READ | PROT_WRITE);
  std::memset(p, 0xFF, rounded);
  if (open_launches.load() == 0) mprotect(p, rounded, PROT_NONE);
  allocation_bytes[p] = rounded;
  return p;
}

void emulated_free(void* p) {
  if (!p) return;
  const std::lock_guard<std::mutex> lock(allocation_mutex);
  const auto it = allocation_bytes.find(p);
  if (it == allocation_bytes.end()) throw std::logic_error("emulated_free: not the debug device's memory");
  madvise(p, it->second, MADV_DONTNEED);  // its memory goes back; the addresses stay reserved
  allocation_bytes.erase(it);
}

bool emulated_accessible(const void* p) {
  const auto address = reinterpret_cast<std::uintptr_t>(p);
  return !p || (address >= range_base.load() && address < range_base.load() + range_used.load());
}

long long emulated_host_touches() { return host_touches.load(); }
long long emulated_launches() { return launches.load(); }

EmulatedLaunch::EmulatedLaunch() {
  if (open_launches.fetch_add(1) == 0) {
    set_access(PROT_READ | PROT_WRITE);
    launches.fetch_add(1);
  }
}

EmulatedLaunch::~EmulatedLaunch() {
  if (open_launches.fetch_sub(1) == 1) set_access(PROT_NONE);
}

}  // namespace isph
