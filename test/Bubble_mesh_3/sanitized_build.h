// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Whether this test binary is built with AddressSanitizer (scripts/sanitize,
// the build in which CI runs the unit tests: 15-25x slower than Release). The
// heaviest tests run a smaller share of their cases there (each says which),
// so that CI stays within its 90 minutes; a Release build runs them whole.
#ifndef BUBBLE_MESH_3_TEST_SANITIZED_BUILD_H
#define BUBBLE_MESH_3_TEST_SANITIZED_BUILD_H

#if defined(__SANITIZE_ADDRESS__)
constexpr bool sanitized_build = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool sanitized_build = true;
#else
constexpr bool sanitized_build = false;
#endif
#else
constexpr bool sanitized_build = false;
#endif

#endif // BUBBLE_MESH_3_TEST_SANITIZED_BUILD_H
