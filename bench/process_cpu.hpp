// CPU time of another process, for the load scripts' probes (not part of the package's code).
#pragma once

#include <unistd.h>

#include <fstream>
#include <sstream>
#include <string>

/// utime + stime of process `pid` so far [s], from /proc/PID/stat.
inline double cpuSecondsOf(int pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  std::getline(stat, line);
  std::istringstream fields(line.substr(line.rfind(')') + 2));  // after "pid (comm) "
  std::string field;
  double ticks = 0.0;
  for (int i = 3; i <= 15 && fields >> field; ++i) {
    if (i == 14 || i == 15) ticks += std::stod(field);  // utime, stime
  }
  return ticks / static_cast<double>(sysconf(_SC_CLK_TCK));
}
