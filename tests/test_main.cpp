// Test entry point; every test's scratch folder is removed when it ends (test_dir.h).
#include <gtest/gtest.h>

#include "test_dir.h"

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ::testing::UnitTest::GetInstance()->listeners().Append(new testutil::TestDirCleaner);
  return RUN_ALL_TESTS();
}
