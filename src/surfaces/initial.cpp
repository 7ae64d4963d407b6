#include "surfaces/initial.h"

#include <muParser.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <exception>
#include <memory>
#include <optional>
#include <random>
#include <stdexcept>
#include <string_view>
#include <type_traits>

#include "parallel/first_exception.h"

namespace cmcsurf {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr std::string_view kExprPrefix = "expr:";

// Cell centre x_i = (i + 1/2) h; a division so that centres on a dyadic value are exact.
double cell_centre(int i, int n) { return (i + 0.5) / n; }

// cos and sin of X and of 2X for one coordinate X = 2 pi x. Every built-in nodal function is a
// polynomial in these, so a grid takes them once per axis index instead of once per cell (the
// values, and so F's bits, are those of std::cos(X), std::cos(2 * X), ... per cell).
struct AxisTrig {
  double c = 1.0, s = 0.0, c2 = 1.0, s2 = 0.0;
};
AxisTrig axis_trig(double X) {
  return {std::cos(X), std::sin(X), std::cos(2 * X), std::sin(2 * X)};
}

// Recurring Fourier terms of the nodal functions below.
double sum_cos(const AxisTrig& x, const AxisTrig& y, const AxisTrig& z) { return x.c + y.c + z.c; }
double sum_cos2(const AxisTrig& x, const AxisTrig& y, const AxisTrig& z) {
  return x.c2 + y.c2 + z.c2;
}
double sum_cos_cos(const AxisTrig& x, const AxisTrig& y, const AxisTrig& z) {
  return x.c * y.c + y.c * z.c + z.c * x.c;
}
double sum_cos2_cos2(const AxisTrig& x, const AxisTrig& y, const AxisTrig& z) {
  return x.c2 * y.c2 + y.c2 * z.c2 + z.c2 * x.c2;
}
// sin 2X sin Z cos Y + sin 2Y sin X cos Z + sin 2Z sin Y cos X: the {211} terms of Ia-3d.
double sum_sin2_sin_cos(const AxisTrig& x, const AxisTrig& y, const AxisTrig& z) {
  return x.s2 * z.s * y.c + y.s2 * x.s * z.c + z.s2 * y.s * x.c;
}

using NodalFn = double (*)(const AxisTrig& x, const AxisTrig& y, const AxisTrig& z);

struct NodalSurface {
  const char* name;
  const char* description;
  bool balanced;  // checked numerically in initial_test.cpp (SurfacesBalance)
  NodalFn F;      // phase 1 = {F > 0}; phi^{step 1} = F + 1/2
};

// The nodal functions F, one place each, of X = 2 pi x, Y = 2 pi y, Z = 2 pi z (their AxisTrig).
// "balanced": some isometry of the cell maps F to -F (both phases congruent).
const NodalSurface kNodal[] = {
    {"P", "Schwarz P, Eq. (7): cos X + cos Y + cos Z (Schnering & Nesper 1991)", true,
     [](const AxisTrig& x, const AxisTrig& y, const AxisTrig& z) { return sum_cos(x, y, z); }},
    {"D",
     "Schwarz D, Eq. (8): cos X cos Y cos Z - sin X sin Y sin Z (= the four-term "
     "Schnering & Nesper 1991 form up to a mirror, a shift by 1/8 and a factor)",
     true,
     [](const AxisTrig& x, const AxisTrig& y, const AxisTrig& z) {
       return x.c * y.c * z.c - x.s * y.s * z.s;
     }},
    {"G",
     "Schoen gyroid, Eq. (9): sin X cos Y + sin Z cos X + sin Y cos Z (Schnering & Nesper 1991)",
     true,
     [](const AxisTrig& x, const AxisTrig& y, const AxisTrig& z) {
       return x.s * y.c + z.s * x.c + y.s * z.c;
     }},
    {"IWP",
     "Schoen I-WP: 2 (cos X cos Y + cos Y cos Z + cos Z cos X) - (cos 2X + cos 2Y + cos 2Z) "
     "(Schnering & Nesper 1991)",
     false,
     [](const AxisTrig& x, const AxisTrig& y, const AxisTrig& z) {
       return 2 * sum_cos_cos(x, y, z) - sum_cos2(x, y, z);
     }},
    {"Neovius",
     "Neovius C(P): 3 (cos X + cos Y + cos Z) + 4 cos X cos Y cos Z (Schnering & Nesper 1991)",
     true,
     [](const AxisTrig& x, const AxisTrig& y, const AxisTrig& z) {
       return 3 * sum_cos(x, y, z) + 4 * x.c * y.c * z.c;
     }},
    {"FRD",
     "Schoen F-RD: 4 cos X cos Y cos Z - (cos 2X cos 2Y + cos 2Y cos 2Z + cos 2Z cos 2X) "
     "(Schnering & Nesper 1991)",
     false,
     [](const AxisTrig& x, const AxisTrig& y, const AxisTrig& z) {
       return 4 * x.c * y.c * z.c - sum_cos2_cos2(x, y, z);
     }},
    {"Lidinoid",
     "Lidinoid: (sin 2X sin Z cos Y + sin 2Y sin X cos Z + sin 2Z sin Y cos X)/2 - (cos 2X cos 2Y "
     "+ cos 2Y cos 2Z + cos 2Z cos 2X)/2 + 0.15 (level surface of Wohlgemuth et al. 2001, halved)",
     false,
     [](const AxisTrig& x, const AxisTrig& y, const AxisTrig& z) {
       return 0.5 * sum_sin2_sin_cos(x, y, z) - 0.5 * sum_cos2_cos2(x, y, z) + 0.15;
     }},
    {"SplitP",
     "Split P: 1.1 (sin 2X sin Z cos Y + sin 2Y sin X cos Z + sin 2Z sin Y cos X) - 0.2 (cos 2X "
     "cos 2Y + cos 2Y cos 2Z + cos 2Z cos 2X) - 0.4 (cos 2X + cos 2Y + cos 2Z) (Wohlgemuth et al. "
     "2001)",
     false,
     [](const AxisTrig& x, const AxisTrig& y, const AxisTrig& z) {
       return 1.1 * sum_sin2_sin_cos(x, y, z) - 0.2 * sum_cos2_cos2(x, y, z) -
              0.4 * sum_cos2(x, y, z);
     }},
    {"FKS",
     "Fischer-Koch S: cos 2X sin Y cos Z + cos 2Y sin Z cos X + cos 2Z sin X cos Y "
     "(Wohlgemuth et al. 2001)",
     true,
     [](const AxisTrig& x, const AxisTrig& y, const AxisTrig& z) {
       return x.c2 * y.s * z.c +
              y.c2 * z.s * x.c +
              z.c2 * x.s * y.c;
     }},
    {"DoubleP",
     "double P (two parallel P sheets): 0.5 (cos X cos Y + cos Y cos Z + cos Z cos X) + 0.2 "
     "(cos 2X + cos 2Y + cos 2Z) (Wohlgemuth et al. 2001)",
     false,
     [](const AxisTrig& x, const AxisTrig& y, const AxisTrig& z) {
       return 0.5 * sum_cos_cos(x, y, z) + 0.2 * sum_cos2(x, y, z);
     }},
    {"DoubleD",
     "double D (two parallel D sheets): cos 2X cos 2Y + cos 2Y cos 2Z + cos 2Z cos 2X + sin 2X "
     "sin 2Y sin 2Z (Wohlgemuth et al. 2001)",
     false,
     [](const AxisTrig& x, const AxisTrig& y, const AxisTrig& z) {
       return sum_cos2_cos2(x, y, z) + x.s2 * y.s2 * z.s2;
     }},
    {"DoubleG",
     "double gyroid (two parallel G sheets): 2.75 (sin 2X sin Z cos Y + sin 2Y sin X cos Z + sin "
     "2Z sin Y cos X) - (cos 2X cos 2Y + cos 2Y cos 2Z + cos 2Z cos 2X) (Wohlgemuth et al. 2001)",
     false,
     [](const AxisTrig& x, const AxisTrig& y, const AxisTrig& z) {
       return 2.75 * sum_sin2_sin_cos(x, y, z) - sum_cos2_cos2(x, y, z);
     }},
};

const NodalSurface* find_nodal(const std::string& name) {
  for (const NodalSurface& s : kNodal)
    if (name == s.name) return &s;
  return nullptr;
}

bool is_expr(const std::string& name) { return name.rfind(kExprPrefix, 0) == 0; }

std::string accepted_names() {
  std::string names;
  for (const SurfaceInfo& s : builtin_surfaces()) names += s.name + ", ";
  return names + "or expr:<formula in x, y, z>";
}

[[noreturn]] void throw_unknown(const std::string& name) {
  throw std::invalid_argument("unknown surface '" + name + "'; accepted: " + accepted_names());
}

// A user nodal function F(x, y, z), x, y, z in [0, 2 pi) over the cell. One instance per
// thread: muParser evaluates through pointers to the variables it owns.
class UserFormula {
 public:
  explicit UserFormula(const std::string& surface) {
    const std::string formula = surface.substr(kExprPrefix.size());
    if (formula.find_first_not_of(" \t") == std::string::npos)
      throw std::invalid_argument("surface '" + surface + "': empty formula after 'expr:'");
    try {
      parser_.DefineConst("pi", std::numbers::pi);
      parser_.DefineVar("x", &x_);
      parser_.DefineVar("y", &y_);
      parser_.DefineVar("z", &z_);
      parser_.SetExpr(formula);
      parser_.Eval();  // muParser reports most syntax errors on the first evaluation
    } catch (const mu::Parser::exception_type& e) {
      std::string msg = e.GetMsg();
      while (!msg.empty() && (msg.back() == '.' || msg.back() == ' ')) msg.pop_back();
      const int pos = static_cast<int>(e.GetPos());
      if (pos >= 0 && msg.find("position") == std::string::npos)
        msg += " at position " + std::to_string(pos);
      if (pos >= 0) msg += " (positions count from 0 in '" + formula + "')";
      throw std::invalid_argument("invalid formula in surface '" + surface + "': " + msg);
    }
  }
  UserFormula(const UserFormula&) = delete;
  UserFormula& operator=(const UserFormula&) = delete;

  double operator()(double X, double Y, double Z) {
    x_ = X;
    y_ = Y;
    z_ = Z;
    return parser_.Eval();
  }

 private:
  double x_ = 0.0, y_ = 0.0, z_ = 0.0;
  mu::Parser parser_;
};

// Fills the interior with value(x, y, z) at cell centres (x, y, z in [0, 1)). `make` builds a
// per-thread evaluator. Exceptions are caught where they arise (every thread must still reach
// the worksharing loop) and the first one is rethrown after the parallel region.
template <class MakeEvaluator>
void fill_at_cell_centres(Field& phi, MakeEvaluator&& make) {
  const int n = phi.n(), nx = phi.nx(), ny = phi.ny(), nz = phi.nz();
  const auto& o = phi.offset();  // block cells sit at global index offset + local index
  FirstException errors;
#pragma omp parallel
  {
    std::optional<std::invoke_result_t<MakeEvaluator&>> value;
    errors.run([&] { value.emplace(make()); });
#pragma omp for schedule(static)
    for (int k = 0; k < nz; ++k) {
      if (!value) continue;
      errors.run([&] {
        for (int j = 0; j < ny; ++j)
          for (int i = 0; i < nx; ++i)
            phi(i, j, k) = (*value)(cell_centre(o[0] + i, n), cell_centre(o[1] + j, n),
                                    cell_centre(o[2] + k, n));
      });
    }
  }
  errors.rethrow();
}

// Uniform in [-1, 1) from the top 53 bits, so the stream is the same with every standard
// library (std::uniform_real_distribution is not specified bit for bit).
double uniform_pm1(std::mt19937_64& rng) {
  return 2.0 * (double(rng() >> 11) * 0x1.0p-53) - 1.0;
}

}  // namespace

const std::vector<SurfaceInfo>& builtin_surfaces() {
  static const std::vector<SurfaceInfo> surfaces = [] {
    std::vector<SurfaceInfo> v;
    for (const NodalSurface& s : kNodal) v.push_back({s.name, s.description, true, s.balanced});
    v.push_back({"sphere",
                 "ball of radius --radius about (1/2, 1/2, 1/2) with a tanh profile of width "
                 "epsilon (Section 4.3)",
                 false, false});
    v.push_back({"cube", "phi = 1 on [1/4, 3/4]^3, 0 elsewhere (Section 4.2)", false, false});
    v.push_back({"noise", "noise_mean + noise_amplitude * rand(-1, 1) per cell (Section 4.1)",
                 false, false});
    return v;
  }();
  return surfaces;
}

// Names are case-sensitive ("G", not "g"): exact match only, so that a name in a report
// always means the same formula.
const SurfaceInfo* find_surface(const std::string& name) {
  for (const SurfaceInfo& s : builtin_surfaces())
    if (s.name == name) return &s;
  return nullptr;
}

bool is_nodal_surface(const std::string& name) {
  return find_nodal(name) != nullptr || is_expr(name);
}

void validate_surface(const std::string& name) {
  if (is_expr(name)) {
    UserFormula check(name);
    return;
  }
  if (!find_surface(name)) throw_unknown(name);
}

double nodal_value(const std::string& surface, double x, double y, double z) {
  if (const NodalSurface* s = find_nodal(surface))
    return s->F(axis_trig(kTwoPi * x), axis_trig(kTwoPi * y), axis_trig(kTwoPi * z)) + 0.5;
  if (is_expr(surface)) {
    // One parser per thread, rebuilt when the formula changes.
    thread_local std::string cached_surface;
    thread_local std::unique_ptr<UserFormula> cached;
    if (!cached || cached_surface != surface) {
      cached.reset();
      cached = std::make_unique<UserFormula>(surface);
      cached_surface = surface;
    }
    return (*cached)(kTwoPi * x, kTwoPi * y, kTwoPi * z) + 0.5;
  }
  if (find_surface(surface))
    throw std::invalid_argument("surface '" + surface + "' is not a nodal surface");
  throw_unknown(surface);
}

Field make_initial_field(const InitialFieldParams& params, int n, int ghost,
                         std::shared_ptr<const Decomposition> decomposition) {
  const std::string& name = params.surface;
  if (decomposition && decomposition->distributed() && name == "noise") {
    // The random stream runs over the whole grid: draw it all, keep this block.
    const Field whole = make_initial_field(params, n, ghost);
    Field phi(n, ghost, decomposition);
    take_block(whole, phi);
    phi.exchange_halo();
    return phi;
  }
  Field phi(n, ghost, decomposition);

  if (const NodalSurface* s = find_nodal(name)) {
    // phi^{step 1} = F + 1/2 (Eqs. 7-9), from the trigonometric values of each axis index.
    std::vector<AxisTrig> trig(n);
    for (int i = 0; i < n; ++i) trig[i] = axis_trig(kTwoPi * cell_centre(i, n));
    const NodalFn F = s->F;
    const auto& o = phi.offset();
    const int nx = phi.nx(), ny = phi.ny(), nz = phi.nz();
#pragma omp parallel for schedule(static)
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j) {
        const AxisTrig& y = trig[o[1] + j];
        const AxisTrig& z = trig[o[2] + k];
        double* row = &phi(0, j, k);
        for (int i = 0; i < nx; ++i) row[i] = F(trig[o[0] + i], y, z) + 0.5;
      }
  } else if (is_expr(name)) {
    UserFormula check(name);  // report a bad formula before entering the parallel region
    fill_at_cell_centres(phi, [&name] {
      return [formula = std::make_shared<UserFormula>(name)](double x, double y, double z) {
        return (*formula)(kTwoPi * x, kTwoPi * y, kTwoPi * z) + 0.5;
      };
    });
    const auto& o = phi.offset();
    for (int k = 0; k < phi.nz(); ++k)
      for (int j = 0; j < phi.ny(); ++j)
        for (int i = 0; i < phi.nx(); ++i)
          if (!std::isfinite(phi(i, j, k)))
            throw std::invalid_argument(
                "surface '" + name + "' is not finite at the cell centre (" +
                std::to_string(cell_centre(o[0] + i, n)) + ", " +
                std::to_string(cell_centre(o[1] + j, n)) + ", " +
                std::to_string(cell_centre(o[2] + k, n)) + ") of the unit cell");
  } else if (name == "sphere") {
    // Section 4.3: phi = (1 + tanh((r - |x - c|) / (2 sqrt 2 epsilon))) / 2, c = (1/2, 1/2, 1/2).
    const double r = params.radius, w = 2.0 * std::sqrt(2.0) * params.epsilon;
    fill_at_cell_centres(phi, [r, w] {
      return [r, w](double x, double y, double z) {
        const double d = std::sqrt((x - 0.5) * (x - 0.5) + (y - 0.5) * (y - 0.5) +
                                   (z - 0.5) * (z - 0.5));
        return 0.5 * (1.0 + std::tanh((r - d) / w));
      };
    });
  } else if (name == "cube") {
    // Section 4.2: phi = 1 if 0.25 <= x, y, z <= 0.75, else 0.
    fill_at_cell_centres(phi, [] {
      return [](double x, double y, double z) {
        const auto in = [](double t) { return 0.25 <= t && t <= 0.75; };
        return (in(x) && in(y) && in(z)) ? 1.0 : 0.0;
      };
    });
  } else if (name == "noise") {
    // Section 4.1: mean + amplitude * rand(-1, 1), one draw per cell in (k, j, i) order, serial
    // so that the field does not depend on the thread count.
    std::mt19937_64 rng(params.seed);
    for_each_cell(n, [&](int i, int j, int k) {
      phi(i, j, k) = params.noise_mean + params.noise_amplitude * uniform_pm1(rng);
    });
  } else {
    throw_unknown(name);
  }

  phi.exchange_halo();
  return phi;
}

}  // namespace cmcsurf
