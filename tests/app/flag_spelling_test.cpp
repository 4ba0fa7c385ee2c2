// app/flag_spelling: the library's `member` names as the command line's flags.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "app/flag_spelling.hpp"

namespace lieflow {
namespace app {
namespace {

TEST(FlagSpelling, BackquotedMembersBecomeFlags) {
  EXPECT_EQ(spellFlags("`max_steps`: needs 10 steps"), "--max-steps: needs 10 steps");
  EXPECT_EQ(spellFlags("`estimator` likelihood with `use` orientations"),
            "--estimator likelihood with --use orientations");
  EXPECT_EQ(spellFlags("raise it with `max_input_mb`"), "raise it with --max-input-mb");
  EXPECT_EQ(spellFlags("`stiffness_start`/`damping_start`"), "--stiffness-start/--damping-start");
  // What is not a lower-case name between backquotes is left as it is.
  for (const char* kept : {"no option here", "a ` lone backquote", "`Upper`", "`two words`", "`x", "x`", "``",
                           "`9lives`", "`a-b`"})
    EXPECT_EQ(spellFlags(kept), kept) << kept;
  EXPECT_EQ(spellFlags("``use``"), "`--use`");
}

TEST(FlagSpelling, EveryStringOfAJsonObject) {
  const nlohmann::ordered_json j = {{"low_pass_reason", "asked for (`low_pass` none)"},
                                    {"segments", {{{"note", "`use` both"}}, 3}},
                                    {"`key`", 1.5}};
  const nlohmann::ordered_json spelled = spellFlagsIn(j);
  EXPECT_EQ(spelled["low_pass_reason"], "asked for (--low-pass none)");
  EXPECT_EQ(spelled["segments"][0]["note"], "--use both");
  EXPECT_EQ(spelled["segments"][1], 3);
  EXPECT_EQ(spelled["`key`"], 1.5);  // keys are the output's names, left as they are
}

}  // namespace
}  // namespace app
}  // namespace lieflow
