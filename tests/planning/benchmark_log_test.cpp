// The OMPL benchmark log is read by OMPL's own ompl_benchmark_statistics into a database.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "planning/ompl_benchmark_log.h"
#include "test_support/temp_dir.h"

namespace terramesh::planning {
namespace {

BenchmarkExperiment smallExperiment(const std::string& map_type) {
  BenchmarkExperiment experiment;
  experiment.name = "terramesh_plan";
  experiment.parameters = {{"map_type", map_type}};
  experiment.setup = "two hand-written runs per planner";
  experiment.time_limit_s = 1;
  experiment.run_count = 2;
  experiment.total_time_s = 3.5;
  const std::vector<std::string> properties = {"time REAL", "solved BOOLEAN", "surface length REAL", "path cost REAL"};
  experiment.planners.push_back({"geometric_RRTstar", properties, {{1.0, 1, 12.5, 20.0}, {1.0, 0, NAN, NAN}}});
  experiment.planners.push_back({"geometric_BITstar", properties, {{0.9, 1, 12.25, 19.5}, {1.0, 1, 12.0, 19.0}}});
  return experiment;
}

TEST(OmplBenchmarkLogTest, OmplStatisticsScriptBuildsADatabaseWithEveryRun) {
  const std::filesystem::path script = "/usr/bin/ompl_benchmark_statistics";
  if (!std::filesystem::exists(script)) GTEST_SKIP() << "ompl-demos is not installed";
  test::TempDir dir;
  writeOmplBenchmarkLog(dir / "mesh.log", smallExperiment("mesh"));
  writeOmplBenchmarkLog(dir / "octomap.log", smallExperiment("octomap"));
  const std::string db = (dir / "bench.db").string();
  const std::string run = "python3 " + script.string() + " " + (dir / "mesh.log").string() + " " +
                          (dir / "octomap.log").string() + " -d " + db + " > " + (dir / "script.txt").string() + " 2>&1";
  ASSERT_EQ(std::system(run.c_str()), 0) << run;
  const std::string query =
      "python3 -c \"import sqlite3; c = sqlite3.connect('" + db +
      "').cursor(); "
      "print(c.execute('SELECT count(*) FROM runs').fetchone()[0]); "
      "print(c.execute('SELECT count(*) FROM runs WHERE solved = 1').fetchone()[0]); "
      "print(' '.join(sorted(r[0] for r in c.execute('SELECT map_type FROM experiments')))); "
      "print(c.execute('SELECT sum(surface_length) FROM runs').fetchone()[0])\" > " +
      (dir / "query.txt").string();
  ASSERT_EQ(std::system(query.c_str()), 0);
  std::ifstream in(dir / "query.txt");
  int runs = 0, solved = 0;
  std::string mesh, octomap;
  double length_sum = 0;
  in >> runs >> solved >> mesh >> octomap >> length_sum;
  EXPECT_EQ(runs, 8);
  EXPECT_EQ(solved, 6);
  EXPECT_EQ(mesh, "mesh");
  EXPECT_EQ(octomap, "octomap");
  EXPECT_NEAR(length_sum, 2 * (12.5 + 12.25 + 12.0), 1e-9);
}

TEST(OmplBenchmarkLogTest, RunsWithTheWrongValueCountAreRefused) {
  BenchmarkExperiment experiment = smallExperiment("mesh");
  experiment.planners[0].runs[1].pop_back();
  EXPECT_THROW(formatOmplBenchmarkLog(experiment), std::invalid_argument);
}

}  // namespace
}  // namespace terramesh::planning
