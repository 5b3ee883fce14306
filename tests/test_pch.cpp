// The translation unit that builds the tests' precompiled header (target lashid_test_pch, tests/CMakeLists.txt).
