/* Preloaded into rayverify (LD_PRELOAD) by threads_test.cpp: pthread_create
 * fails with EAGAIN once FIXTURE_THREADS_ALLOWED threads were created (0 when
 * unset), as it does under a container's pid limit on a machine with many
 * cores. The threads it lets through are created by the C library's own. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

typedef int (*create_fn)(pthread_t*, const pthread_attr_t*, void* (*)(void*), void*);

int pthread_create(pthread_t* thread, const pthread_attr_t* attr, void* (*start)(void*), void* arg) {
    static atomic_int created = 0;
    const char* allowed = getenv("FIXTURE_THREADS_ALLOWED");
    if (atomic_fetch_add(&created, 1) >= (allowed ? atoi(allowed) : 0)) return EAGAIN;
    create_fn real;
    void* symbol = dlsym(RTLD_NEXT, "pthread_create");
    memcpy(&real, &symbol, sizeof real); /* POSIX: a function's address through dlsym's void* */
    return real(thread, attr, start, arg);
}
