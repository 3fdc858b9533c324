#include "server/priority_inheritance_mutex.h"

#include <cerrno>
#include <system_error>

namespace mobot::server {

namespace {

void check(int error, const char* what) {
  if (error != 0) throw std::system_error(error, std::generic_category(), what);
}

}  // namespace

PriorityInheritanceMutex::PriorityInheritanceMutex() {
  pthread_mutexattr_t attributes;
  check(pthread_mutexattr_init(&attributes), "pthread_mutexattr_init");
  const int protocol = pthread_mutexattr_setprotocol(&attributes, PTHREAD_PRIO_INHERIT);
  const int init = protocol == 0 ? pthread_mutex_init(&mutex_, &attributes) : protocol;
  pthread_mutexattr_destroy(&attributes);
  check(init, "a priority-inheritance mutex");
}

PriorityInheritanceMutex::~PriorityInheritanceMutex() { pthread_mutex_destroy(&mutex_); }

void PriorityInheritanceMutex::lock() { check(pthread_mutex_lock(&mutex_), "pthread_mutex_lock"); }

void PriorityInheritanceMutex::unlock() { pthread_mutex_unlock(&mutex_); }

}  // namespace mobot::server
