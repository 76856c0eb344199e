// LD_PRELOAD shim for the thread-limit test (reliability_test.cc): pthread_create succeeds TETHER_THREADS_ALLOWED
// times (default 1), then fails with EAGAIN, as a process limit on threads (ulimit -u) makes it fail.
#include <dlfcn.h>
#include <pthread.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>

namespace {
std::atomic<int> created{0};
}  // namespace

extern "C" int pthread_create(pthread_t* thread, const pthread_attr_t* attributes, void* (*start)(void*),
                              void* argument) {
  const char* allowed = std::getenv("TETHER_THREADS_ALLOWED");
  if (created++ >= (allowed ? std::atoi(allowed) : 1)) return EAGAIN;
  using Create = int (*)(pthread_t*, const pthread_attr_t*, void* (*)(void*), void*);
  const auto real = reinterpret_cast<Create>(dlsym(RTLD_NEXT, "pthread_create"));
  return real(thread, attributes, start, argument);
}
