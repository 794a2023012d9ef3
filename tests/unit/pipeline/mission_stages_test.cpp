// The one table of stages (pipeline/io/stage_outputs.hpp) and the functions bound to its rows
// (pipeline/stages/mission_runner.hpp): every row runs, in the table's order, and a name not in the
// table is a usage error.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "config/error.hpp"
#include "pipeline/io/output_paths.hpp"
#include "pipeline/io/stage_outputs.hpp"
#include "pipeline/stages/mission_runner.hpp"
#include "support/expect_error.hpp"

namespace rangecal {
namespace {

TEST(MissionStages, EveryRowOfTheTableHasItsFunctionInOrder) {
  const std::vector<MissionStage>& table = mission_stage_table();
  const std::vector<NamedStage>& stages = mission_stages();
  ASSERT_EQ(stages.size(), table.size());
  for (std::size_t i = 0; i < table.size(); ++i) {
    EXPECT_EQ(stages[i].name, table[i].name);
    EXPECT_TRUE(static_cast<bool>(stages[i].run)) << table[i].name;
    EXPECT_EQ(mission_stage_names()[i], table[i].name);
  }
  EXPECT_EQ(mission_stage_names(), (std::vector<std::string>{"gnss", "align", "detect", "calibrate",
                                                             "intersect", "trajectory", "report"}));
}

TEST(MissionStages, EachStageWritesFilesNoOtherStageWrites) {
  MissionConfig cfg;
  cfg.output_dir = "out";
  cfg.cameras.resize(2);
  cfg.cameras[0].id = "c1";
  cfg.cameras[1].id = "c2";
  std::vector<std::string> seen;
  for (const MissionStage& s : mission_stage_table()) {
    const std::vector<std::string> files = stage_output_files(cfg, s.name);
    EXPECT_FALSE(files.empty()) << s.name;
    for (const std::string& f : files) {
      EXPECT_EQ(std::count(seen.begin(), seen.end(), f), 0) << f << " written by two stages";
      seen.push_back(f);
    }
  }
  EXPECT_EQ(stage_output_files(cfg, "gnss"), std::vector<std::string>{lamp_track_path(cfg)});
  EXPECT_EQ(stage_output_files(cfg, "align"),
            (std::vector<std::string>{camera_output(cfg, "c1", kAlignedCsv),
                                      camera_output(cfg, "c2", kAlignedCsv)}));
}

TEST(MissionStages, AnUnknownStageIsAUsageError) {
  MissionConfig cfg;
  cfg.output_dir = "out";
  const std::vector<Error> errors = {
      test::expect_error([&] { stage_output_files(cfg, "calibarte"); }),
      test::expect_error([&] { remove_outputs_from_stage(cfg, "calibarte"); }),
      test::expect_error([&] { run_stage("calibarte", cfg); }),
  };
  for (const Error& e : errors) {
    EXPECT_EQ(e.kind(), ErrorKind::usage);
    EXPECT_NE(std::string(e.what()).find("'calibarte'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rangecal
