// tests/precompiled.cpp: an empty unit, the owner of the tests' precompiled header
// (tests/CMakeLists.txt: varsym_test_pch).
