// The translation unit that builds the tests' precompiled header
// (support/precompiled.h, tests/CMakeLists.txt); it holds nothing else.
