// Tests that take tens of seconds under ASan + UBSan (their code runs 3 to 10 times slower there) and whose code
// paths shorter tests already check under the sanitizers: skipped in the sanitizer build (LASHID_UNDER_SANITIZERS,
// set by tests/CMakeLists.txt), run in every other build. This keeps CI's run within its time (docs/architecture.md,
// "CI's time"); the skip names the tests that cover the same paths.
#pragma once

#include <gtest/gtest.h>

#if defined(LASHID_UNDER_SANITIZERS)
#define LASHID_SKIP_UNDER_SANITIZERS(covered_by) \
  GTEST_SKIP() << "long under the sanitizers; the same paths are checked there by " << (covered_by)
#else
#define LASHID_SKIP_UNDER_SANITIZERS(covered_by) static_cast<void>(0)
#endif
