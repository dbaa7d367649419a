#include "CommandFile.h"

#include <fstream>
#include <sstream>
#include <vector>

bool CommandFile::find(const std::string& command, TraceParams& out) const
{
    std::ifstream in(mPath);
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') {
            continue;
        }
        std::vector<std::string> cells;
        std::stringstream row(line);
        std::string cell;
        while (std::getline(row, cell, ',')) {
            cells.push_back(cell);
        }
        if (cells.size() < 7 || cells[0] != command) {
            continue;
        }
        out.distance_mm = std::stoi(cells[2]);
        out.power = std::stoi(cells[3]);
        out.kp = std::stof(cells[4]);
        out.ki = std::stof(cells[5]);
        out.kd = std::stof(cells[6]);
        return true;
    }
    return false;
}
