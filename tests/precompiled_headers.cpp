// Empty: the target qdmeta_test_headers (tests/CMakeLists.txt) exists to build the precompiled
// headers that every test program reuses; a target needs one source of its own.
