// ParamReader on a map of values instead of the parameter server: types, ranges, choices, typos, the log line.

#include <gmock/gmock.h>

#include <map>

#include "thorvald_common/ros/param_reader.h"

using testing::HasSubstr;
using thorvald_common::ParamError;
using thorvald_common::ParamRange;
using thorvald_common::ParamReader;

namespace {

class MapSource : public thorvald_common::ParamSource {
 public:
  explicit MapSource(std::map<std::string, XmlRpc::XmlRpcValue> values) : values_(std::move(values)) {}
  bool get(const std::string& name, XmlRpc::XmlRpcValue& value) const override {
    const auto it = values_.find(name);
    if (it == values_.end()) return false;
    value = it->second;
    return true;
  }
  std::vector<std::string> names() const override {
    std::vector<std::string> out;
    for (const auto& kv : values_) out.push_back(kv.first);
    return out;
  }

 private:
  std::map<std::string, XmlRpc::XmlRpcValue> values_;
};

ParamReader reader(std::map<std::string, XmlRpc::XmlRpcValue> values) {
  return ParamReader(std::make_unique<MapSource>(std::move(values)), "/robot/base_driver");
}

/// The message of the ParamError that `read` throws; fails the test if none is thrown.
template <typename F>
std::string errorOf(F read) {
  try {
    read();
  } catch (const ParamError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no ParamError";
  return "";
}

}  // namespace

TEST(ParamReader, DefaultsWhenUnset) {
  ParamReader r = reader({});
  EXPECT_DOUBLE_EQ(r.number("rate", 50.0, ParamRange::aboveUpTo(0, 1000), "Hz"), 50.0);
  EXPECT_EQ(r.integer("seed", 7), 7);
  EXPECT_TRUE(r.flag("simple_sim", true));
  EXPECT_EQ(r.text("tf_prefix", "abc"), "abc");
  EXPECT_EQ(r.choice("odometry_estimator", "least_squares", {"least_squares", "random_pairs"}), "least_squares");
  EXPECT_EQ(r.effectiveValues(),
            "rate=50 (default), seed=7 (default), simple_sim=true (default), tf_prefix='abc' (default), "
            "odometry_estimator=least_squares (default)");
  EXPECT_TRUE(r.finish().empty());
}

TEST(ParamReader, ReadsSetValues) {
  ParamReader r = reader({{"rate", XmlRpc::XmlRpcValue(20)},
                          {"timeout", XmlRpc::XmlRpcValue(0.25)},
                          {"seed", XmlRpc::XmlRpcValue(3.0)},
                          {"simple_sim", XmlRpc::XmlRpcValue(false)},
                          {"estimator", XmlRpc::XmlRpcValue("random_pairs")}});
  EXPECT_DOUBLE_EQ(r.number("rate", 50.0, ParamRange::aboveUpTo(0, 1000), "Hz"), 20.0);  // int accepted
  EXPECT_DOUBLE_EQ(r.number("timeout", 0.5, ParamRange::above(0), "s"), 0.25);
  EXPECT_EQ(r.integer("seed", 1, 0), 3);  // integral double accepted
  EXPECT_FALSE(r.flag("simple_sim", true));
  EXPECT_EQ(r.choice("estimator", "least_squares", {"least_squares", "random_pairs"}), "random_pairs");
  EXPECT_THAT(r.effectiveValues(), HasSubstr("rate=20, timeout=0.25, seed=3, simple_sim=false"));
  EXPECT_TRUE(r.unread().empty());
}

TEST(ParamReader, RefusesWrongTypes) {
  ParamReader r = reader({{"simple_sim", XmlRpc::XmlRpcValue("maybe")},
                          {"rate", XmlRpc::XmlRpcValue("fast")},
                          {"seed", XmlRpc::XmlRpcValue(1.5)},
                          {"tf_prefix", XmlRpc::XmlRpcValue(12)},
                          {"flag_as_int", XmlRpc::XmlRpcValue(1)}});
  const std::string sim = errorOf([&] { r.flag("simple_sim", true); });
  EXPECT_THAT(sim, HasSubstr("/robot/base_driver: parameter ~simple_sim: found the string 'maybe'"));
  EXPECT_THAT(sim, HasSubstr("expected true or false"));
  const std::string rate = errorOf([&] { r.number("rate", 50.0, ParamRange::aboveUpTo(0, 1000), "Hz"); });
  EXPECT_THAT(rate, HasSubstr("~rate: found the string 'fast', expected a number in (0, 1000] [Hz]"));
  EXPECT_THAT(errorOf([&] { r.integer("seed", 1); }), HasSubstr("found the number 1.5, expected an integer"));
  EXPECT_THAT(errorOf([&] { r.text("tf_prefix", ""); }), HasSubstr("found the integer 12, expected a string"));
  EXPECT_THAT(errorOf([&] { r.flag("flag_as_int", false); }), HasSubstr("found the integer 1"));
}

TEST(ParamReader, RefusesValuesOutsideTheirRange) {
  ParamReader r = reader({{"rate", XmlRpc::XmlRpcValue(0)},
                          {"big", XmlRpc::XmlRpcValue(1001.0)},
                          {"count", XmlRpc::XmlRpcValue(-1)},
                          {"estimator", XmlRpc::XmlRpcValue("magic")},
                          {"nan", XmlRpc::XmlRpcValue(std::nan(""))}});
  EXPECT_THAT(errorOf([&] { r.number("rate", 50, ParamRange::aboveUpTo(0, 1000), "Hz"); }),
              HasSubstr("found the integer 0, expected a number in (0, 1000] [Hz]"));
  EXPECT_THAT(errorOf([&] { r.number("big", 50, ParamRange::aboveUpTo(0, 1000)); }), HasSubstr("(0, 1000]"));
  EXPECT_THAT(errorOf([&] { r.integer("count", 20, 1, 1000); }), HasSubstr("expected an integer in [1, 1000]"));
  EXPECT_THAT(errorOf([&] {
                r.choice("estimator", "least_squares", {"least_squares", "random_pairs"});
              }),
              HasSubstr("found the string 'magic', expected one of 'least_squares', 'random_pairs'"));
  EXPECT_THAT(errorOf([&] { r.number("nan", 1.0, ParamRange::any()); }), HasSubstr("expected a number"));
}

TEST(ParamReader, RangeBoundsAreExactlyAsDeclared) {
  EXPECT_FALSE(ParamRange::above(0).contains(0.0));
  EXPECT_TRUE(ParamRange::atLeast(0).contains(0.0));
  EXPECT_TRUE(ParamRange::aboveUpTo(0, 10).contains(10.0));
  EXPECT_FALSE(ParamRange::aboveUpTo(0, 10).contains(10.0000001));
  EXPECT_FALSE(ParamRange::any().contains(std::nan("")));
  EXPECT_EQ(ParamRange::atLeast(0).text(), ">= 0");
  EXPECT_EQ(ParamRange::closed(-1, 2.5).text(), "[-1, 2.5]");
}

TEST(ParamReader, WarnsAboutUnreadParametersWithTheNearestName) {
  ParamReader r = reader({{"cmd_vel_timout", XmlRpc::XmlRpcValue(0.1)},
                          {"rate", XmlRpc::XmlRpcValue(50)},
                          {"diagnostic_period", XmlRpc::XmlRpcValue(1.0)},
                          {"limits/vx", XmlRpc::XmlRpcValue(1.0)},
                          {"completely_unrelated_name", XmlRpc::XmlRpcValue(1)}});
  r.number("cmd_vel_timeout", 0.5, ParamRange::above(0), "s");
  r.number("rate", 50, ParamRange::aboveUpTo(0, 1000), "Hz");
  r.alsoRead("diagnostic_period");
  r.alsoRead("limits");
  EXPECT_EQ(r.unread(), (std::vector<std::string>{"cmd_vel_timout", "completely_unrelated_name"}));
  const auto warnings = r.finish();
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_THAT(warnings[0], HasSubstr("~cmd_vel_timout is set but nothing in this node reads it"));
  EXPECT_THAT(warnings[0], HasSubstr("did you mean ~cmd_vel_timeout?"));
  EXPECT_THAT(warnings[1], testing::Not(HasSubstr("did you mean")));
}

TEST(ParamReader, HasCountsAsRead) {
  ParamReader r = reader({{"extra", XmlRpc::XmlRpcValue(1)}});
  EXPECT_TRUE(r.has("extra"));
  EXPECT_FALSE(r.has("other"));
  EXPECT_TRUE(r.unread().empty());
}

namespace {
XmlRpc::XmlRpcValue list(std::initializer_list<XmlRpc::XmlRpcValue> values) {
  XmlRpc::XmlRpcValue out;
  out.setSize(static_cast<int>(values.size()));
  int i = 0;
  for (const auto& v : values) out[i++] = v;
  return out;
}
}  // namespace

TEST(ParamReader, ReadsLists) {
  ParamReader r = reader({{"gains", list({XmlRpc::XmlRpcValue(1), XmlRpc::XmlRpcValue(0.5)})},
                          {"sensors", list({XmlRpc::XmlRpcValue("left"), XmlRpc::XmlRpcValue("right")})},
                          {"mask", list({XmlRpc::XmlRpcValue(true), XmlRpc::XmlRpcValue(false)})}});
  EXPECT_EQ(r.numbers("gains", {}, ParamRange::atLeast(0), "", 2, 2), (std::vector<double>{1.0, 0.5}));
  EXPECT_EQ(r.texts("sensors", {}, 1, 8, true), (std::vector<std::string>{"left", "right"}));
  EXPECT_EQ(r.flags("mask", {}), (std::vector<bool>{true, false}));
  EXPECT_EQ(r.numbers("unset", {3.0}, ParamRange::any()), (std::vector<double>{3.0}));
  EXPECT_THAT(r.effectiveValues(),
              HasSubstr("gains=[1, 0.5], sensors=['left', 'right'], mask=[true, false], unset=[3] (default)"));
  EXPECT_TRUE(r.finish().empty());
}

TEST(ParamReader, RefusesBadListsNamingTheElement) {
  ParamReader r = reader({{"not_a_list", XmlRpc::XmlRpcValue(1.0)},
                          {"short", list({XmlRpc::XmlRpcValue(1.0)})},
                          {"negative", list({XmlRpc::XmlRpcValue(1.0), XmlRpc::XmlRpcValue(-2.0)})},
                          {"mixed", list({XmlRpc::XmlRpcValue("a"), XmlRpc::XmlRpcValue(2)})},
                          {"twice", list({XmlRpc::XmlRpcValue("a"), XmlRpc::XmlRpcValue("a")})},
                          {"bools", list({XmlRpc::XmlRpcValue(true), XmlRpc::XmlRpcValue("no")})}});
  EXPECT_THAT(errorOf([&] { r.numbers("not_a_list", {}, ParamRange::any()); }),
              HasSubstr("~not_a_list: found the number 1, expected a list, each a number"));
  EXPECT_THAT(errorOf([&] { r.numbers("short", {}, ParamRange::any(), "m", 2, 2); }),
              HasSubstr("found a list of 1 values, expected a list of exactly 2 elements"));
  EXPECT_THAT(errorOf([&] { r.numbers("negative", {}, ParamRange::atLeast(0)); }),
              HasSubstr("~negative[1]: found the number -2, expected a number in >= 0"));
  EXPECT_THAT(errorOf([&] { r.texts("mixed", {}); }), HasSubstr("~mixed[1]: found the integer 2, expected a string"));
  EXPECT_THAT(errorOf([&] { r.texts("twice", {}, 0, 10, true); }), HasSubstr("~twice[1]: found the string 'a'"));
  EXPECT_THAT(errorOf([&] { r.flags("bools", {}); }), HasSubstr("~bools[1]: found the string 'no'"));
}

TEST(ParamReader, RawAndRejectedParameters) {
  XmlRpc::XmlRpcValue tree;
  tree["vx"] = 1.0;
  ParamReader r = reader({{"limits", tree}, {"limits/vx", XmlRpc::XmlRpcValue(1.0)}, {"odom_frame_id", 1}});
  XmlRpc::XmlRpcValue got;
  EXPECT_TRUE(r.raw("limits", &got));
  EXPECT_EQ(got.getType(), XmlRpc::XmlRpcValue::TypeStruct);
  EXPECT_FALSE(r.raw("absent", &got));
  EXPECT_THAT(errorOf([&] { r.reject("odom_frame_id", "this node publishes no odometry"); }),
              HasSubstr("~odom_frame_id is not supported: this node publishes no odometry"));
  r.reject("other_unset", "never set, never an error");
  EXPECT_TRUE(r.unread().empty());
}
