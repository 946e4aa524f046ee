// fk_tool: UR5 forward kinematics for fkcheck's external-program protocol.
//
// stdin:  one configuration per line, 6 comma-separated joint angles in radians
//         (shoulder_pan, shoulder_lift, elbow, wrist_1, wrist_2, wrist_3).
//         Blank lines are skipped.
// stdout: per configuration, one line of 16 numbers: base_T_tool0 as a 4x4
//         matrix, row-major, each printed with %.17g (exact round trip).
// errors: a line that is not 6 finite numbers -> message on stderr, exit 1.
//
// Model: the nominal UR5 table from Universal Robots, standard DH
//   A_i = Rz(theta_i) * Tz(d_i) * Tx(a_i) * Rx(alpha_i),  theta_i = q_i.

#include <Eigen/Geometry>

#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>

namespace {

constexpr double kPi = 3.141592653589793238462643383279502884;

struct DhRow {
  double a;      // link length, m
  double d;      // link offset, m
  double alpha;  // link twist, rad
};

constexpr int kDof = 6;

constexpr std::array<DhRow, kDof> kUr5 = {{
    {0.0, 0.089159, kPi / 2},
    {-0.425, 0.0, 0.0},
    {-0.39225, 0.0, 0.0},
    {0.0, 0.10915, kPi / 2},
    {0.0, 0.09465, -kPi / 2},
    {0.0, 0.0823, 0.0},
}};

// Standard DH link transform, written as the product it is defined by.
Eigen::Isometry3d linkTransform(const DhRow& row, double theta) {
  Eigen::Isometry3d A = Eigen::Isometry3d::Identity();
  A.rotate(Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitZ()));
  A.translate(Eigen::Vector3d(0.0, 0.0, row.d));
  A.translate(Eigen::Vector3d(row.a, 0.0, 0.0));
  A.rotate(Eigen::AngleAxisd(row.alpha, Eigen::Vector3d::UnitX()));
  return A;
}

Eigen::Isometry3d forwardKinematics(const std::array<double, kDof>& q) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (int i = 0; i < kDof; ++i) {
    T = T * linkTransform(kUr5[i], q[i]);
  }
  return T;
}

bool isBlank(const std::string& s) {
  return s.find_first_not_of(" \t\r") == std::string::npos;
}

// Parse "q1,q2,...,q6" (spaces around numbers allowed). On failure, sets `why`.
bool parseLine(const std::string& line, std::array<double, kDof>& q, std::string& why) {
  const char* p = line.c_str();
  for (int i = 0; i < kDof; ++i) {
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(p, &end);
    if (end == p) {
      why = "field " + std::to_string(i + 1) + " is not a number";
      return false;
    }
    if (errno == ERANGE || !std::isfinite(v)) {
      why = "field " + std::to_string(i + 1) + " is not a finite number";
      return false;
    }
    q[i] = v;
    while (*end == ' ' || *end == '\t' || *end == '\r') ++end;
    if (i + 1 < kDof) {
      if (*end != ',') {
        why = "expected 6 comma-separated numbers, got " + std::to_string(i + 1);
        return false;
      }
      p = end + 1;
    } else if (*end != '\0') {
      why = "expected 6 comma-separated numbers, got more (or trailing text)";
      return false;
    }
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1) {
    std::fprintf(stderr,
                 "usage: %s < joints.csv\n"
                 "  reads lines of 6 comma-separated UR5 joint angles (rad), prints\n"
                 "  16 numbers per line: base_T_tool0 row-major (%%.17g)\n",
                 argv[0]);
    return 2;
  }
  std::string line;
  long lineno = 0;
  std::array<double, kDof> q{};
  while (std::getline(std::cin, line)) {
    ++lineno;
    if (isBlank(line)) continue;
    std::string why;
    if (!parseLine(line, q, why)) {
      std::fprintf(stderr, "fk_tool: line %ld: %s: '%s'\n", lineno, why.c_str(), line.c_str());
      return 1;
    }
    const Eigen::Matrix4d M = forwardKinematics(q).matrix();
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) {
        std::printf(r == 0 && c == 0 ? "%.17g" : " %.17g", M(r, c));
      }
    }
    std::putchar('\n');
  }
  if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
    std::fprintf(stderr, "fk_tool: cannot write to stdout\n");
    return 1;
  }
  return 0;
}
