// Where this checkout's examples and test data are. The paths are defined in a file generated at
// configure time (cmake/source_paths.cpp.in), not by -D flags, so that compiled test objects do not
// embed the checkout's absolute path and a compiler cache shares them between checkouts.
#pragma once

namespace ringlet_test {
const char* ExamplesDir();
const char* TestDataDir();
}  // namespace ringlet_test

#define RINGLET_EXAMPLES_DIR (::ringlet_test::ExamplesDir())
#define RINGLET_TEST_DATA_DIR (::ringlet_test::TestDataDir())
