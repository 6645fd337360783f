// MAGENC_IGNORE_THIRD_PARTY_LEAKS: in sanitizer builds (scripts/san_build.sh), what OpenMPI and its
// dlopen'ed components allocate while MPI starts and stops is theirs (uninstrumented, never freed by
// design, reported from unmapped modules that no suppression can name); LeakSanitizer ignores
// allocations made in the scope where this macro stands. Elsewhere it is nothing.
#pragma once

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define MAGENC_LSAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define MAGENC_LSAN 1
#endif
#ifdef MAGENC_LSAN
#include <sanitizer/lsan_interface.h>
#define MAGENC_IGNORE_THIRD_PARTY_LEAKS __lsan::ScopedDisabler lsan_off
#else
#define MAGENC_IGNORE_THIRD_PARTY_LEAKS
#endif
