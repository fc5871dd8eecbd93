// Pinocchio's C++ algorithms timed on the robots of this repository; see bench/README.md.
//
// Built by bench/run.sh from Pinocchio's headers alone with -O3 -march=native (every algorithm is
// instantiated here; only boost_serialization is linked).  The models come in as binary files that
// run.sh writes with Pinocchio's Python package (URDF -> Model::saveToBinary), so no Model or Data
// object crosses between this code and the packaged, differently compiled libraries.
//
// usage: pinocchio_bench [--calls N] [--reps R] [--count ALGO] name=model.bin ...
// output: one line per (robot, algorithm): "robot nv algorithm median_ns min_ns"
// --count ALGO: no timing and no warm-up, only N calls of ALGO, for instruction counts under
// callgrind (run.sh with CALLGRIND=1 takes the difference of two call counts).

#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/rnea-derivatives.hpp>
#include <pinocchio/algorithm/aba-derivatives.hpp>
#include <pinocchio/serialization.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <random>
#include <string>
#include <vector>

using Eigen::VectorXd;

static volatile double g_sink = 0.0;

// Median and minimum ns per call over `reps` timed loops of `calls` calls each.
static std::pair<double, double> time_it(long calls, int reps, const std::function<double(long)> & f)
{
  double s = 0;
  for (long i = 0; i < std::min<long>(calls / 10 + 1, 20000); ++i) // warm-up
    s += f(i);
  std::vector<double> per;
  for (int r = 0; r < reps; ++r)
  {
    const auto t0 = std::chrono::steady_clock::now();
    for (long i = 0; i < calls; ++i)
      s += f(i);
    const auto t1 = std::chrono::steady_clock::now();
    per.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / double(calls));
  }
  g_sink = g_sink + s;
  std::sort(per.begin(), per.end());
  return {per[per.size() / 2], per.front()};
}

int main(int argc, char ** argv)
{
  long calls = 100000;
  int reps = 5;
  std::string count;
  std::vector<std::pair<std::string, std::string>> robots;
  for (int i = 1; i < argc; ++i)
  {
    const std::string s = argv[i];
    if (s == "--calls" && i + 1 < argc)
      calls = std::atol(argv[++i]);
    else if (s == "--reps" && i + 1 < argc)
      reps = std::atoi(argv[++i]);
    else if (s == "--count" && i + 1 < argc)
      count = argv[++i];
    else if (s.find('=') != std::string::npos)
      robots.push_back({s.substr(0, s.find('=')), s.substr(s.find('=') + 1)});
    else
    {
      std::fprintf(stderr, "bad argument %s (expected name=model.bin)\n", s.c_str());
      return 2;
    }
  }

  const int K = 1024; // random states, cycled through (fixed seed)
  for (const auto & rp : robots)
  {
    pinocchio::Model model;
    model.loadFromBinary(rp.second);
    // 1-dof joints only, after an optional free flyer (joint 1: position, quaternion).
    const bool free_flyer = model.njoints > 1 && model.joints[1].shortname() == "JointModelFreeFlyer";
    if (model.nq != model.nv + (free_flyer ? 1 : 0))
    {
      std::fprintf(stderr, "%s: only revolute/prismatic joints (and a free-flyer root) are supported\n", rp.first.c_str());
      return 2;
    }
    pinocchio::Data data(model);
    std::mt19937_64 gen(12345u);
    std::uniform_real_distribution<double> ang(-M_PI, M_PI), u(-2.0, 2.0);
    std::vector<VectorXd> q(K), v(K), a(K), tau(K);
    for (int k = 0; k < K; ++k)
    {
      q[k] = VectorXd::NullaryExpr(model.nq, [&]() { return ang(gen); });
      if (free_flyer)
        q[k].segment<4>(3).normalize(); // a unit quaternion (x, y, z, w)
      v[k] = VectorXd::NullaryExpr(model.nv, [&]() { return u(gen); });
      a[k] = VectorXd::NullaryExpr(model.nv, [&]() { return u(gen); });
      tau[k] = VectorXd::NullaryExpr(model.nv, [&]() { return 5.0 * u(gen); });
    }
    const int n = model.nv;
    Eigen::MatrixXd dg = Eigen::MatrixXd::Zero(n, n);
    { // sanity: rnea(q, v, aba(q, v, tau)) == tau
      const VectorXd ddq = pinocchio::aba(model, data, q[3], v[3], tau[3]);
      const double err = (pinocchio::rnea(model, data, q[3], v[3], ddq) - tau[3]).cwiseAbs().maxCoeff();
      if (!(err < 1e-8))
      {
        std::fprintf(stderr, "%s: rnea/aba mismatch %g\n", rp.first.c_str(), err);
        return 3;
      }
    }
    const std::vector<std::pair<const char *, std::function<double(long)>>> algos = {
      {"rnea", [&](long i) { const int k = i & (K - 1); return pinocchio::rnea(model, data, q[k], v[k], a[k])[0]; }},
      // c(q, v) + g(q): rnea at zero acceleration
      {"nle", [&](long i) { const int k = i & (K - 1); return pinocchio::nonLinearEffects(model, data, q[k], v[k])[0]; }},
      // upper triangle only, as Pinocchio leaves it
      {"crba", [&](long i) { const int k = i & (K - 1); return pinocchio::crba(model, data, q[k])(0, n - 1); }},
      {"gravity", [&](long i) { const int k = i & (K - 1); return pinocchio::computeGeneralizedGravity(model, data, q[k])[0]; }},
      {"aba", [&](long i) { const int k = i & (K - 1); return pinocchio::aba(model, data, q[k], v[k], tau[k])[0]; }},
      // dtau/dq, dtau/dv and dtau/da = M (upper triangle) in data
      {"rnea_derivatives", [&](long i) {
         const int k = i & (K - 1);
         pinocchio::computeRNEADerivatives(model, data, q[k], v[k], a[k]);
         return data.dtau_dq(n - 1, 0) + data.dtau_dv(n - 1, 0);
       }},
      // ddq (data.ddq), ddq/dq, ddq/dv and M^-1 (upper triangle) in data
      {"aba_derivatives", [&](long i) {
         const int k = i & (K - 1);
         pinocchio::computeABADerivatives(model, data, q[k], v[k], tau[k]);
         return data.ddq_dq(n - 1, 0) + data.ddq_dv(n - 1, 0);
       }},
      // M^-1, upper triangle
      {"minverse", [&](long i) {
         const int k = i & (K - 1);
         pinocchio::computeMinverse(model, data, q[k]);
         return data.Minv(0, n - 1);
       }},
      // dg/dq
      {"gravity_derivatives", [&](long i) {
         const int k = i & (K - 1);
         pinocchio::computeGeneralizedGravityDerivatives(model, data, q[k], dg);
         return dg(n - 1, 0);
       }},
    };
    for (const auto & al : algos)
    {
      if (!count.empty())
      {
        if (count != al.first)
          continue;
        double sum = 0;
        for (long i = 0; i < calls; ++i)
          sum += al.second(i);
        g_sink = g_sink + sum;
        std::printf("%-16s %3d %-8s %ld calls\n", rp.first.c_str(), n, al.first, calls);
        continue;
      }
      const auto r = time_it(calls, reps, al.second);
      std::printf("%-16s %3d %-8s %10.1f %10.1f\n", rp.first.c_str(), n, al.first, r.first, r.second);
      std::fflush(stdout);
    }
  }
  return 0;
}
