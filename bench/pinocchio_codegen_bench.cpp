// Pinocchio's *code-generated* derivatives (CppADCodeGen) timed on the robots of this repository;
// see bench/README.md.  Built and run by bench/run_codegen.sh.
//
// For each robot (a binary model file, written from a URDF by Pinocchio's Python package as in
// bench/run.sh; fixed-base chains of 1-dof joints only) and each of six algorithms
//   cg_rnea              CodeGenRNEA:            x = (q, v, a)   -> y = tau
//   cg_crba              CodeGenCRBA:            x = q           -> y = upper triangle of M, row by row
//   cg_aba               CodeGenABA:             x = (q, v, tau) -> y = qdd
//   cg_rnea_derivatives  CodeGenRNEADerivatives: x = (q, v, a)   -> y = (dtau/dq, dtau/dv, dtau/da), each nv x nv
//                        row-major; dtau/da = M with only its upper triangle filled (as Pinocchio leaves it)
//   cg_aba_derivatives   CodeGenABADerivatives:  x = (q, v, tau) -> y = (dqdd/dq, dqdd/dv, dqdd/dtau = M^-1),
//                        each nv x nv row-major
//   cg_minverse          CodeGenMinv:            x = q          -> y = upper triangle of M^-1, row by row
// this program
//   1. traces the algorithm with Pinocchio's own code generator (pinocchio/codegen/cppadcg-algo.hpp,
//      Scalar = double, i.e. CppAD::AD<CppAD::cg::CG<double>>), which records the operations and lets
//      CppAD optimize the tape,
//   2. has CppADCodeGen write the C source and compile it into a shared library with the given C compiler
//      and flags (default: gcc -O3 -march=native; Pinocchio's own compileLib would use -Ofast and takes
//      the flags as one argv string), unless the library already exists in --lib-dir,
//   3. loads the library (dlopen) and checks the generated function against plain Pinocchio (compiled
//      into this binary) at 16 of the states: max |generated - plain| / max |plain| must be <= 1e-9,
//      otherwise the program stops with exit code 3 before timing anything,
//   4. times the generated function alone: GenericModel::ForwardZero(x, y) on input vectors packed
//      beforehand (no copies, no unpacking of y; one virtual call and CppADCodeGen's argument checks
//      around the generated C function), cycling through 1024 random states.  The sampler and seed are
//      those of bench/pinocchio_bench.cpp (q uniform in [-pi, pi], v and a in [-2, 2], tau in [-10, 10],
//      std::mt19937_64 seeded with 12345).  Median and minimum ns/call over R repetitions of N calls;
//      the repetitions of the six algorithms of a robot are interleaved so that a change of load on
//      a shared machine hits all of them alike.
//
// usage: pinocchio_codegen_bench [--calls N] [--reps R] [--lib-dir DIR] [--cc PATH] [--cflags "FLAGS"]
//                                name=model.bin ...
//   Generated libraries go to DIR/<name>/<algo>_<model name>.so, their C sources to DIR/<name>/src_<algo>/.
//   A library already there is loaded as it is: whoever changes the model, this program or the flags must
//   clear DIR (bench/run_codegen.sh keys DIR on all three).
// output:
//   # build <robot> <algo> trace_s=.. codegen_and_cc_s=.. c_bytes=.. reused=0|1      (to stdout, comments)
//   # check <robot> <algo> states=16 max_abs_diff=.. max_abs_ref=.. rel=.. OK|FAIL
//   <robot> <nv> <algo> <median_ns> <min_ns>

#include <pinocchio/codegen/cppadcg.hpp> // first: declares the CppAD scalar traits the other headers use
#include <pinocchio/codegen/cppadcg-algo.hpp>

#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/aba-derivatives.hpp>
#include <pinocchio/algorithm/rnea-derivatives.hpp>
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/serialization.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

using Eigen::MatrixXd;
using Eigen::VectorXd;
namespace fs = std::filesystem;

static volatile double g_sink = 0.0;

static double seconds_since(std::chrono::steady_clock::time_point t0)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Pinocchio's code generator G, with the pieces CodeGenBase keeps protected: compiling with a flag vector,
// the existence of the library, and the generated function itself.
template<class G>
struct Exposed : G
{
  using G::G;

  // CodeGenBase::compileLib, with the compile flags as separate arguments and the C sources kept on disk
  void compile(const std::string & cc, const std::vector<std::string> & flags, const std::string & dir, const std::string & tag)
  {
    CppAD::cg::GccCompiler<double> compiler(cc);
    compiler.setCompileFlags(flags); // replaces CppADCodeGen's {"-O2"}; the link step keeps -O2 -shared -rdynamic
    compiler.setTemporaryFolder(dir + "/tmp_" + tag);
    compiler.setSaveToDiskFirst(true);
    compiler.setSourcesFolder(dir + "/src_" + tag);
    this->dynamicLibManager_ptr->createDynamicLibrary(compiler, false);
    fs::remove_all(dir + "/tmp_" + tag); // object files
  }
  bool exists() const
  {
    return this->existLib();
  }
  // the generated function: y = f(x)
  void forward_zero(const double * x, double * y)
  {
    this->generatedFun_ptr->ForwardZero(
      CppAD::cg::ArrayView<const double>(x, (size_t)this->getInputDimension()),
      CppAD::cg::ArrayView<double>(y, (size_t)this->getOutputDimension()));
  }
};

// One generated algorithm of one robot, ready to time.
struct Timed
{
  std::string algo;
  long nx, ny;
  std::vector<double> X, Y; // 1024 packed inputs; one output
  std::function<void(const double *, double *)> f;
  std::vector<double> per; // ns/call, one entry per repetition
};

static long bytes_under(const std::string & dir)
{
  long n = 0;
  if (fs::is_directory(dir))
    for (const auto & e : fs::directory_iterator(dir))
      if (e.is_regular_file())
        n += (long)e.file_size();
  return n;
}

// Trace, generate, compile (or reuse), load and check one algorithm.
// pack(k, x): input vector of state k; reference(k): plain Pinocchio's answer laid out like y.
template<class G>
static Timed prepare(
  const pinocchio::Model & model,
  const std::string & robot,
  const std::string & algo,
  const std::string & dir,
  const std::string & cc,
  const std::vector<std::string> & flags,
  int K,
  const std::function<void(int, VectorXd &)> & pack,
  const std::function<VectorXd(int)> & reference)
{
  fs::create_directories(dir);
  auto t0 = std::chrono::steady_clock::now();
  auto gen = std::make_shared<Exposed<G>>(model, algo, dir + "/" + algo); // library: <algo>_<model name>.so
  gen->initLib(); // trace and optimize; sets up the C source generator
  const double trace_s = seconds_since(t0);
  const bool reused = gen->exists();
  double compile_s = 0;
  if (!reused)
  {
    t0 = std::chrono::steady_clock::now();
    gen->compile(cc, flags, dir, algo);
    compile_s = seconds_since(t0);
  }
  gen->loadLib(false);
  std::printf(
    "# build %s %s trace_s=%.2f codegen_and_cc_s=%.2f c_bytes=%ld reused=%d\n", robot.c_str(), algo.c_str(), trace_s,
    compile_s, bytes_under(dir + "/src_" + algo), reused ? 1 : 0);
  std::fflush(stdout);

  Timed t;
  t.algo = algo;
  t.nx = gen->getInputDimension();
  t.ny = gen->getOutputDimension();
  t.X.resize((size_t)(t.nx * K));
  t.Y.resize((size_t)t.ny);
  VectorXd x(t.nx);
  for (int k = 0; k < K; ++k)
  {
    pack(k, x);
    std::copy(x.data(), x.data() + t.nx, t.X.begin() + (long)k * t.nx);
  }
  t.f = [gen](const double * xi, double * yi) { gen->forward_zero(xi, yi); };

  // correctness against plain Pinocchio
  const int states = 16;
  double diff = 0, ref_max = 0, rel = 0;
  for (int s = 0; s < states; ++s)
  {
    const int k = (s * 67) % K;
    t.f(t.X.data() + (long)k * t.nx, t.Y.data());
    const VectorXd r = reference(k);
    if (r.size() != t.ny)
    {
      std::fprintf(stderr, "%s %s: output size %ld, reference size %ld\n", robot.c_str(), algo.c_str(), t.ny, (long)r.size());
      std::exit(3);
    }
    const double d = (Eigen::Map<const VectorXd>(t.Y.data(), t.ny) - r).cwiseAbs().maxCoeff();
    const double m = r.cwiseAbs().maxCoeff();
    diff = std::max(diff, d);
    ref_max = std::max(ref_max, m);
    rel = std::max(rel, m > 0 ? d / m : d);
    if (!std::isfinite(d))
      rel = INFINITY;
  }
  const bool ok = rel <= 1e-9;
  std::printf(
    "# check %s %s states=%d max_abs_diff=%.3e max_abs_ref=%.3e rel=%.2e %s\n", robot.c_str(), algo.c_str(), states,
    diff, ref_max, rel, ok ? "OK" : "FAIL");
  std::fflush(stdout);
  if (!ok)
  {
    std::fprintf(
      stderr, "CHECK FAILED: %s %s: generated code differs from plain Pinocchio by %.3e relative (> 1e-9)\n",
      robot.c_str(), algo.c_str(), rel);
    std::exit(3);
  }
  return t;
}

// Repetitions interleaved: rep 1 of every algorithm, then rep 2, ...
static void time_interleaved(std::vector<Timed> & ts, long calls, int reps, int K)
{
  double s = 0;
  auto loop = [&](Timed & t, long n) {
    for (long i = 0; i < n; ++i)
    {
      t.f(t.X.data() + (i & (K - 1)) * t.nx, t.Y.data());
      s += t.Y[0];
    }
  };
  for (auto & t : ts) // warm-up
    loop(t, std::min<long>(calls / 10 + 1, 20000));
  for (int r = 0; r < reps; ++r)
    for (auto & t : ts)
    {
      loop(t, std::min<long>(calls / 100 + 1, 1000)); // caches and branch predictors back on this function
      const auto t0 = std::chrono::steady_clock::now();
      loop(t, calls);
      const auto t1 = std::chrono::steady_clock::now();
      t.per.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / double(calls));
    }
  g_sink = g_sink + s;
}

// upper triangle, row by row
static VectorXd upper_rows(const MatrixXd & M)
{
  const long n = M.rows();
  VectorXd r(n * (n + 1) / 2);
  long it = 0;
  for (long i = 0; i < n; ++i)
    for (long j = i; j < n; ++j)
      r[it++] = M(i, j);
  return r;
}

// three n x n matrices, each row-major, one after the other
static VectorXd three_row_major(const MatrixXd & A, const MatrixXd & B, const MatrixXd & C)
{
  const long n = A.rows();
  VectorXd r(3 * n * n);
  long it = 0;
  for (const MatrixXd * M : {&A, &B, &C})
    for (long i = 0; i < n; ++i)
      for (long j = 0; j < n; ++j)
        r[it++] = (*M)(i, j);
  return r;
}

static std::vector<std::string> split_ws(const std::string & s)
{
  std::istringstream is(s);
  std::vector<std::string> r;
  std::string w;
  while (is >> w)
    r.push_back(w);
  return r;
}

int main(int argc, char ** argv)
{
  long calls = 100000;
  int reps = 5;
  std::string lib_dir = "codegen", cc = "/usr/bin/gcc";
  std::vector<std::string> cflags = {"-O3", "-march=native"};
  std::vector<std::pair<std::string, std::string>> robots;
  for (int i = 1; i < argc; ++i)
  {
    const std::string s = argv[i];
    if (s == "--calls" && i + 1 < argc)
      calls = std::atol(argv[++i]);
    else if (s == "--reps" && i + 1 < argc)
      reps = std::atoi(argv[++i]);
    else if (s == "--lib-dir" && i + 1 < argc)
      lib_dir = argv[++i];
    else if (s == "--cc" && i + 1 < argc)
      cc = argv[++i];
    else if (s == "--cflags" && i + 1 < argc)
      cflags = split_ws(argv[++i]);
    else if (s.find('=') != std::string::npos)
      robots.push_back({s.substr(0, s.find('=')), s.substr(s.find('=') + 1)});
    else
    {
      std::fprintf(stderr, "bad argument %s (expected name=model.bin)\n", s.c_str());
      return 2;
    }
  }
  if (calls < 1 || reps < 1)
  {
    std::fprintf(stderr, "--calls and --reps must be positive\n");
    return 2;
  }
  lib_dir = fs::absolute(lib_dir).string(); // dlopen must not search the library path

  const int K = 1024; // random states, cycled through (fixed seed)
  for (const auto & rp : robots)
  {
    const std::string & robot = rp.first;
    pinocchio::Model model;
    model.loadFromBinary(rp.second);
    if (model.nq != model.nv)
    {
      std::fprintf(stderr, "%s: fixed-base chains of 1-dof joints only (nq = %d, nv = %d)\n", robot.c_str(), model.nq, model.nv);
      return 2;
    }
    pinocchio::Data data(model);
    const int n = model.nv;

    // the sampler of bench/pinocchio_bench.cpp, in the same order
    std::mt19937_64 gen(12345u);
    std::uniform_real_distribution<double> ang(-M_PI, M_PI), u(-2.0, 2.0);
    std::vector<VectorXd> q(K), v(K), a(K), tau(K);
    for (int k = 0; k < K; ++k)
    {
      q[k] = VectorXd::NullaryExpr(model.nq, [&]() { return ang(gen); });
      v[k] = VectorXd::NullaryExpr(n, [&]() { return u(gen); });
      a[k] = VectorXd::NullaryExpr(n, [&]() { return u(gen); });
      tau[k] = VectorXd::NullaryExpr(n, [&]() { return 5.0 * u(gen); });
    }

    auto pack_qva = [&](int k, VectorXd & x) { x << q[k], v[k], a[k]; };
    auto pack_qvt = [&](int k, VectorXd & x) { x << q[k], v[k], tau[k]; };
    auto pack_q = [&](int k, VectorXd & x) { x = q[k]; };
    // plain Pinocchio, into zeroed matrices (the parts it leaves untouched stay 0, as in the traced code)
    auto ref_rnea = [&](int k) { return VectorXd(pinocchio::rnea(model, data, q[k], v[k], a[k])); };
    auto ref_crba = [&](int k) {
      data.M.setZero();
      return upper_rows(pinocchio::crba(model, data, q[k], pinocchio::Convention::WORLD));
    };
    auto ref_aba = [&](int k) { return VectorXd(pinocchio::aba(model, data, q[k], v[k], tau[k], pinocchio::Convention::WORLD)); };
    auto ref_rnea_derivatives = [&](int k) {
      MatrixXd dq = MatrixXd::Zero(n, n), dv = MatrixXd::Zero(n, n), da = MatrixXd::Zero(n, n);
      pinocchio::computeRNEADerivatives(model, data, q[k], v[k], a[k], dq, dv, da);
      return three_row_major(dq, dv, da);
    };
    auto ref_aba_derivatives = [&](int k) {
      MatrixXd dq = MatrixXd::Zero(n, n), dv = MatrixXd::Zero(n, n), dtau = MatrixXd::Zero(n, n);
      pinocchio::computeABADerivatives(model, data, q[k], v[k], tau[k], dq, dv, dtau);
      return three_row_major(dq, dv, dtau);
    };
    auto ref_minverse = [&](int k) {
      data.Minv.setZero();
      return upper_rows(pinocchio::computeMinverse(model, data, q[k]));
    };

    using namespace pinocchio;
    const std::string dir = lib_dir + "/" + robot;
    std::vector<Timed> ts;
    ts.push_back(prepare<CodeGenRNEA<double>>(model, robot, "cg_rnea", dir, cc, cflags, K, pack_qva, ref_rnea));
    ts.push_back(prepare<CodeGenCRBA<double>>(model, robot, "cg_crba", dir, cc, cflags, K, pack_q, ref_crba));
    ts.push_back(prepare<CodeGenABA<double>>(model, robot, "cg_aba", dir, cc, cflags, K, pack_qvt, ref_aba));
    ts.push_back(prepare<CodeGenRNEADerivatives<double>>(
      model, robot, "cg_rnea_derivatives", dir, cc, cflags, K, pack_qva, ref_rnea_derivatives));
    ts.push_back(prepare<CodeGenABADerivatives<double>>(
      model, robot, "cg_aba_derivatives", dir, cc, cflags, K, pack_qvt, ref_aba_derivatives));
    ts.push_back(
      prepare<CodeGenMinv<double>>(model, robot, "cg_minverse", dir, cc, cflags, K, pack_q, ref_minverse));

    time_interleaved(ts, calls, reps, K);
    for (auto & t : ts)
    {
      std::sort(t.per.begin(), t.per.end());
      std::printf("%-16s %3d %-20s %10.1f %10.1f\n", robot.c_str(), n, t.algo.c_str(), t.per[t.per.size() / 2], t.per.front());
    }
    std::fflush(stdout);
  }
  return 0;
}
