/* SPDX-License-Identifier: MIT */
/*
 * Counting allocations on a hot path (header-only; include it once, in one test executable):
 * this executable's malloc, calloc and realloc take precedence over libc's for every caller
 * (the libraries under test and theirs included) and count while allocs >= 0. Not under
 * AddressSanitizer or ThreadSanitizer, which bring their own: HL_COUNT_ALLOCS is 0 there.
 */
#ifndef HL_TESTS_ALLOC_COUNT_H
#define HL_TESTS_ALLOC_COUNT_H

#include <stddef.h>

static _Atomic long allocs = -1; /* -1: not counting */

#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define HL_SANITIZER 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define HL_SANITIZER 1
#endif

#if defined(HL_SANITIZER)
#define HL_COUNT_ALLOCS 0
#else
#define HL_COUNT_ALLOCS 1
extern void *__libc_malloc(size_t size);
extern void *__libc_calloc(size_t n, size_t size);
extern void *__libc_realloc(void *p, size_t size);

static void count_alloc(void)
{
	long n = allocs;

	if (n >= 0)
		allocs = n + 1;
}

void *malloc(size_t size)
{
	count_alloc();
	return __libc_malloc(size);
}

void *calloc(size_t n, size_t size)
{
	count_alloc();
	return __libc_calloc(n, size);
}

void *realloc(void *p, size_t size)
{
	count_alloc();
	return __libc_realloc(p, size);
}
#endif

#endif
