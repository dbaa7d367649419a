// Times kerikun11/micromouse-maze-library on one maze file, for scripts/bench_maze_kernel.py to print beside
// mazelog's figures: built against the library by scripts/build_maze_library.sh, never vendored.
//
//   maze_timing query MAZE REPEAT   the median of REPEAT fastest-path queries (diagonal, every wall known),
//                                   in ms: Agent::calcShortestDirections(true) on the true maze
//   maze_timing search MAZE         its whole search (CLRobotBase::searchRun, as its examples/meas does) and
//                                   the four shortest paths meas then finds; time it as a whole process
#include <algorithm>
#include <chrono>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "MazeLib/Agent.h"
#include "MazeLib/CLRobotBase.h"

using MazeLib::Agent;
using MazeLib::CLRobotBase;
using MazeLib::Maze;

namespace {

int query(const Maze& truth, int repeat) {
  const auto agent = std::make_unique<Agent>();
  agent->updateMaze(truth);
  std::vector<double> ms;
  for (int i = 0; i < repeat; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    const bool found = agent->calcShortestDirections(true);
    const auto t1 = std::chrono::steady_clock::now();
    if (!found) {
      std::cerr << "maze_timing: no fastest path" << std::endl;
      return 1;
    }
    ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
  }
  std::sort(ms.begin(), ms.end());
  std::cout << "query_ms " << ms[ms.size() / 2] << " cost_ms " << agent->getSearchAlgorithm().getShortestCost()
            << std::endl;
  return 0;
}

int search(Maze& truth) {
  const auto robot = std::make_unique<CLRobotBase>(truth);
  if (!robot->searchRun()) return 1;
  for (const bool diagonal : {false, true}) {
    const auto agent = std::make_unique<Agent>();
    agent->updateMaze(truth);
    if (!robot->calcShortestDirections(diagonal) || !agent->calcShortestDirections(diagonal)) return 1;
  }
  std::cout << "walls " << robot->getMaze().getWallRecords().size() << " est_ms " << robot->est_time_ms
            << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 2 ? argv[1] : "";
  if ((mode != "query" || argc != 4) && (mode != "search" || argc != 3)) {
    std::cerr << "usage: maze_timing query MAZE REPEAT | maze_timing search MAZE" << std::endl;
    return 2;
  }
  const auto truth = std::make_unique<Maze>();
  std::ifstream file(argv[2]);
  if (!file || !truth->parse(file)) {
    std::cerr << "maze_timing: cannot read a maze from " << argv[2] << std::endl;
    return 2;
  }
  return mode == "query" ? query(*truth, std::stoi(argv[3])) : search(*truth);
}
