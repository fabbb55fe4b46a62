#include "chromatag/bench/run_info.h"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

namespace chromatag::bench {

std::string CpuModel() {
  std::ifstream in("/proc/cpuinfo");
  std::string line, name = "unknown", family, model;
  auto value = [](const std::string& text) {
    const size_t colon = text.find(':');
    const size_t start =
        colon == std::string::npos ? std::string::npos : text.find_first_not_of(" \t", colon + 1);
    return start == std::string::npos ? std::string() : text.substr(start);
  };
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0 && name == "unknown") name = value(line);
    if (line.rfind("cpu family", 0) == 0 && family.empty()) family = value(line);
    if (line.rfind("model\t", 0) == 0 && model.empty()) model = value(line);
  }
  const unsigned cores = std::thread::hardware_concurrency();
  return name + " (family " + family + ", model " + model + "), " + std::to_string(cores) +
         " logical CPUs";
}

std::string LoadAverage() {
  std::ifstream in("/proc/loadavg");
  std::string one, five, fifteen;
  in >> one >> five >> fifteen;
  return one + " / " + five + " / " + fifteen;
}

std::string CommandLine(int argc, char** argv) {
  std::ostringstream command;
  for (int i = 0; i < argc; ++i) {
    const std::string arg = i ? argv[i] : std::filesystem::path(argv[0]).filename().string();
    command << (i ? " " : "") << (arg.find(' ') == std::string::npos ? arg : "'" + arg + "'");
  }
  return command.str();
}

}  // namespace chromatag::bench
