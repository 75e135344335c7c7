// A counting allocator for a program that cannot be rebuilt for the test:
// preloaded (LD_PRELOAD) into troupe-node under qemu-user, it forwards
// every allocation to glibc and counts it. On SIGUSR1 it writes one line to
// stderr:
//   alloc-count: allocations=N frees=N live_bytes=N
// The steady-state test compares two reports taken 100,000 messages apart.
#include <malloc.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <cstdint>

extern "C" {
// glibc's own entry points, which its malloc() forwards to.
void* __libc_malloc(size_t size);
void* __libc_calloc(size_t n, size_t size);
void* __libc_realloc(void* p, size_t size);
void* __libc_memalign(size_t alignment, size_t size);
void __libc_free(void* p);
}

namespace {

// Single-threaded program; volatile so that the signal handler reads what
// the last allocation wrote.
volatile uint64_t g_allocations = 0;
volatile uint64_t g_frees = 0;
volatile int64_t g_live_bytes = 0;

void* counted(void* p) {
  if (p != nullptr) {
    g_allocations = g_allocations + 1;
    g_live_bytes = g_live_bytes + int64_t(malloc_usable_size(p));
  }
  return p;
}

void uncount(void* p) {
  if (p == nullptr) return;
  g_frees = g_frees + 1;
  g_live_bytes = g_live_bytes - int64_t(malloc_usable_size(p));
}

// snprintf is not async-signal-safe: format by hand.
char* put_number(char* at, int64_t value) {
  if (value < 0) {
    *at++ = '-';
    value = -value;
  }
  char digits[24];
  int n = 0;
  do {
    digits[n++] = char('0' + value % 10);
    value /= 10;
  } while (value != 0);
  while (n > 0) *at++ = digits[--n];
  return at;
}

char* put_text(char* at, const char* text) {
  while (*text != '\0') *at++ = *text++;
  return at;
}

void report(int) {
  int saved = errno;
  char line[128];
  char* at = put_text(line, "alloc-count: allocations=");
  at = put_number(at, int64_t(g_allocations));
  at = put_text(at, " frees=");
  at = put_number(at, int64_t(g_frees));
  at = put_text(at, " live_bytes=");
  at = put_number(at, g_live_bytes);
  *at++ = '\n';
  (void)!write(STDERR_FILENO, line, size_t(at - line));
  errno = saved;
}

__attribute__((constructor)) void install_report() {
  struct sigaction sa {};
  sa.sa_handler = report;
  sa.sa_flags = SA_RESTART;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGUSR1, &sa, nullptr);
}

}  // namespace

extern "C" {

void* malloc(size_t size) {
  return counted(__libc_malloc(size));
}
void* calloc(size_t n, size_t size) {
  return counted(__libc_calloc(n, size));
}
void* memalign(size_t alignment, size_t size) {
  return counted(__libc_memalign(alignment, size));
}
void* aligned_alloc(size_t alignment, size_t size) {
  return counted(__libc_memalign(alignment, size));
}
int posix_memalign(void** out, size_t alignment, size_t size) {
  void* p = counted(__libc_memalign(alignment, size));
  if (p == nullptr) return ENOMEM;
  *out = p;
  return 0;
}
void free(void* p) {
  uncount(p);
  __libc_free(p);
}
void* realloc(void* p, size_t size) {
  // Counted as a free of the old block and an allocation of the new one.
  if (p != nullptr && size == 0) {
    free(p);
    return nullptr;
  }
  int64_t old = p ? int64_t(malloc_usable_size(p)) : 0;
  void* q = __libc_realloc(p, size);
  if (q == nullptr) return nullptr;
  if (p != nullptr) {
    g_frees = g_frees + 1;
    g_live_bytes = g_live_bytes - old;
  }
  return counted(q);
}

}  // extern "C"
