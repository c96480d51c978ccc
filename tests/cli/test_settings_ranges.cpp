// The three front doors of a render setting agree on its range: the core
// (RenderSettings::validate()), the JSON scene parser ("render" block) and the
// rayscope command's options. For every limit of render_settings.h, the limit
// itself is accepted by all three and the nearest value beyond it is refused
// by all three, with the same message: the core's, after "FILE: render: " in
// the parser and after "rayscope: error: --OPTION: " in the command.
// The values come from the named limits, so the test follows them.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>

#include "rayscope/render_settings.h"
#include "rayscope/scene_io.h"

namespace {

using rayscope::RenderSettings;

std::string text(float v) {
  char buf[32];
  return std::string(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
}

// One value of one setting, as each front end spells it.
struct Case {
  std::string what;                          // for failure messages
  std::function<void(RenderSettings&)> set;  // the core field(s)
  std::optional<std::string> json;           // the "render" members, if the format has them
  std::string option;                        // the command-line option ...
  std::string option_value;                  // ... and its value
};

// The core's verdict: empty when valid, else validate()'s message.
std::string core(const Case& c) {
  RenderSettings s;
  c.set(s);
  try {
    s.validate();
    return "";
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
}

std::string json_error(const Case& c) {
  try {
    rayscope::parse_scene("{\"render\": {" + *c.json + "}}", "limits.json", ".", nullptr);
    return "";
  } catch (const rayscope::SceneError& e) {
    return e.what();
  }
}

// Runs `rayscope inspect --pixel 0,0 --sample 0 OPTION=VALUE` on the default
// scene (one pixel, one sample: cheap even at the largest image size or sample
// count); returns its stderr, or "" when it succeeded.
std::string cli_error(const Case& c) {
  const std::string cmd = std::string("'") + RAYSCOPE_EXE + "' inspect --pixel 0,0 --sample 0 " +
                          c.option + "=" + c.option_value + " 2>&1 >/dev/null";
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return "popen failed";
  std::string out;
  char buf[512];
  while (size_t n = fread(buf, 1, sizeof buf, p)) out.append(buf, n);
  int status = pclose(p);
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return out.empty() ? "" : "exit 0: " + out;
  if (!WIFEXITED(status) || WEXITSTATUS(status) >= 128) return "crashed: " + out;
  return out.empty() ? "non-zero exit without a message" : out;
}

void expect_all_accept(const Case& c) {
  EXPECT_EQ(core(c), "") << c.what;
  if (c.json) {
    EXPECT_EQ(json_error(c), "") << c.what;
  }
  EXPECT_EQ(cli_error(c), "") << c.what;
}

void expect_all_refuse(const Case& c) {
  const std::string msg = core(c);
  ASSERT_NE(msg, "") << c.what << ": the core accepts it";
  if (c.json) {
    EXPECT_EQ(json_error(c), "limits.json: render: " + msg) << c.what;
  }
  EXPECT_EQ(cli_error(c), "rayscope: error: " + c.option + ": " + msg + "\n") << c.what;
}

// An integer setting with one JSON key and one option.
Case int_case(const char* key, const char* option, int RenderSettings::*field, long long v) {
  const std::string k = key, value = std::to_string(v);
  return {k + " = " + value, [=](RenderSettings& s) { s.*field = int(v); },
          std::string(1, '"').append(k).append("\": ").append(value), option, value};
}

struct IntLimits {
  const char* key;
  const char* option;
  int RenderSettings::*field;
  int lo, hi;
};

TEST(SettingsRanges, IntegerSettingsAgree) {
  using RS = RenderSettings;
  for (const IntLimits& l :
       {IntLimits{"width", "--width", &RS::width, 1, RS::kMaxImageSide},
        IntLimits{"height", "--height", &RS::height, 1, RS::kMaxImageSide},
        IntLimits{"samples", "--spp", &RS::samples, 1, RS::kMaxSamples},
        IntLimits{"max_depth", "--max-depth", &RS::max_depth, 0, RS::kMaxDepth}}) {
    expect_all_accept(int_case(l.key, l.option, l.field, l.lo));
    expect_all_accept(int_case(l.key, l.option, l.field, l.hi));
    expect_all_refuse(int_case(l.key, l.option, l.field, l.lo - 1));
    expect_all_refuse(int_case(l.key, l.option, l.field, l.hi + 1));
  }
}

TEST(SettingsRanges, ThreadsAgree) {
  // Not in the scene format: the core and the command.
  for (long long v : {0LL, (long long)RenderSettings::kMaxThreads}) {
    Case c = int_case("threads", "--threads", &RenderSettings::threads, v);
    c.json.reset();
    expect_all_accept(c);
  }
  for (long long v : {-1LL, RenderSettings::kMaxThreads + 1LL}) {
    Case c = int_case("threads", "--threads", &RenderSettings::threads, v);
    c.json.reset();
    expect_all_refuse(c);
  }
}

TEST(SettingsRanges, PixelCountAgrees) {
  // The widest image with the most pixels, and one row more.
  const int w = RenderSettings::kMaxImageSide;
  const int h = int(RenderSettings::kMaxPixels / w);
  ASSERT_LE(h, RenderSettings::kMaxImageSide);
  for (int rows : {h, h + 1}) {
    Case c{"size " + std::to_string(w) + "x" + std::to_string(rows),
           [=](RenderSettings& s) {
             s.width = w;
             s.height = rows;
           },
           "\"width\": " + std::to_string(w) + ", \"height\": " + std::to_string(rows), "--size",
           std::to_string(w) + "x" + std::to_string(rows)};
    if (rows == h)
      expect_all_accept(c);
    else
      expect_all_refuse(c);
  }
}

TEST(SettingsRanges, MinContributionAgrees) {
  const float hi = RenderSettings::kMaxMinContribution;
  auto c = [](float v) {
    return Case{"min_contribution = " + text(v), [=](RenderSettings& s) { s.min_contribution = v; },
                "\"min_contribution\": " + text(v), "--min-contribution", text(v)};
  };
  expect_all_accept(c(0.0f));
  expect_all_accept(c(hi));
  // The nearest floats beyond the range (their shortest text reads back exactly).
  expect_all_refuse(c(std::nextafter(0.0f, -1.0f)));
  expect_all_refuse(c(std::nextafter(hi, 2.0f * hi)));
}

TEST(SettingsRanges, AdaptiveSamplingAgrees) {
  // max_samples: 0 or a multiple of samples up to kMaxSamples. The command's
  // default scene takes 2 x 2 samples, the core's and the parser's 1: the
  // command line sets --spp=1 too (applied before --max-spp whatever the order).
  const int hi = RenderSettings::kMaxSamples;
  auto m = [](int v) {
    return Case{"max_samples = " + std::to_string(v), [=](RenderSettings& s) { s.max_samples = v; },
                "\"max_samples\": " + std::to_string(v), "--max-spp",
                std::to_string(v) + " --spp=1"};
  };
  expect_all_accept(m(1));
  expect_all_accept(m(hi));
  expect_all_refuse(m(hi + 1));
  expect_all_refuse(m(-1));
  // target_error: 0..kMaxTargetError, with max_samples set (4).
  const float te = RenderSettings::kMaxTargetError;
  auto t = [](float v) {
    return Case{"target_error = " + text(v),
                [=](RenderSettings& s) {
                  s.max_samples = 4;
                  s.target_error = v;
                },
                "\"max_samples\": 4, \"target_error\": " + text(v), "--target-error",
                text(v) + " --max-spp=4"};
  };
  expect_all_accept(t(0.0f));
  expect_all_accept(t(te));
  expect_all_refuse(t(std::nextafter(0.0f, -1.0f)));
  expect_all_refuse(t(std::nextafter(te, 2.0f * te)));
  // A target without adaptive sampling.
  Case alone{"target_error without max_samples", [](RenderSettings& s) { s.target_error = 0.01f; },
             "\"target_error\": 0.01", "--target-error", "0.01"};
  expect_all_refuse(alone);
}

TEST(SettingsRanges, SeedAgrees) {
  auto c = [](uint32_t v) {
    return Case{"seed = " + std::to_string(v), [=](RenderSettings& s) { s.seed = v; },
                "\"seed\": " + std::to_string(v), "--seed", std::to_string(v)};
  };
  expect_all_accept(c(0));
  expect_all_accept(c(RenderSettings::kMaxSeed));
  expect_all_refuse(c(RenderSettings::kMaxSeed + 1));
  // Below 0 the core's unsigned field cannot even hold the value: the parser and
  // the command refuse it as a wrong type, naming the setting.
  Case minus{"seed = -1", nullptr, "\"seed\": -1", "--seed", "-1"};
  EXPECT_EQ(json_error(minus), "limits.json: render.seed: -1 is not a 32-bit unsigned integer");
  const std::string err = cli_error(minus);
  EXPECT_EQ(err.rfind("rayscope: error: ", 0), 0u) << err;
  EXPECT_NE(err.find("--seed"), std::string::npos) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
}

TEST(SettingsRanges, JsonTypesAreCheckedBeforeRanges) {
  Case big{"width = 1e12", nullptr, "\"width\": 1000000000000", "", ""};
  EXPECT_EQ(json_error(big), "limits.json: render.width: 1000000000000 is not a 32-bit integer");
  Case frac{"samples = 1.5", nullptr, "\"samples\": 1.5", "", ""};
  EXPECT_EQ(json_error(frac), "limits.json: render.samples: expected an integer");
}

}  // namespace
