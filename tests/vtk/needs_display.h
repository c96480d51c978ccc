// Tests that open VTK's OpenGL windows derive their fixture from DisplayTest:
// without an X display, vtkXOpenGLRenderWindow reports "bad X server
// connection" and the program then crashes, so each test is skipped instead,
// with the reason. scripts/test runs them under xvfb-run, which provides one.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>

namespace rayscope_test {

class DisplayTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const char* display = std::getenv("DISPLAY");
    if (display == nullptr || *display == '\0')
      GTEST_SKIP() << "no X display (DISPLAY is unset): run under xvfb-run -a";
  }
};

}  // namespace rayscope_test
