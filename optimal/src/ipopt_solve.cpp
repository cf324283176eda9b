// optimal/src/ipopt_solve.cpp: the IPOPT adapter (a TNLP over an optimal::nlp).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <IpIpoptApplication.hpp>
#include <IpTNLP.hpp>

#include "solve_detail.hpp"
#include "varsym/optimize/solve.hpp"
#include "varsym/run/input_file.hpp"
#include "varsym/run/memory.hpp"

namespace varsym::optimal {

namespace {

using Ipopt::Index;
using Ipopt::Number;

constexpr double ipopt_infinity = 1e19; // IPOPT's nlp_{lower,upper}_bound_inf

status verdict_of(Ipopt::SolverReturn s) {
    switch (s) {
    case Ipopt::SUCCESS:
        return status::solved;
    case Ipopt::STOP_AT_ACCEPTABLE_POINT:
        return status::acceptable;
    case Ipopt::LOCAL_INFEASIBILITY:
        return status::infeasible;
    case Ipopt::MAXITER_EXCEEDED:
    case Ipopt::CPUTIME_EXCEEDED:
        return status::iteration_limit;
    case Ipopt::USER_REQUESTED_STOP:
        return status::interrupted;
    default:
        return status::failed;
    }
}

const char* message_of(Ipopt::SolverReturn s) {
    switch (s) {
    case Ipopt::SUCCESS:
        return "optimal solution found";
    case Ipopt::STOP_AT_ACCEPTABLE_POINT:
        return "solved to IPOPT's acceptable level";
    case Ipopt::LOCAL_INFEASIBILITY:
        return "the problem is locally infeasible: no trajectory near the iterates meets the "
               "boundary states within the bounds (loosen the bounds, lengthen the horizon)";
    case Ipopt::MAXITER_EXCEEDED:
        return "the iteration limit was reached";
    case Ipopt::CPUTIME_EXCEEDED:
        return "the time limit was reached";
    case Ipopt::USER_REQUESTED_STOP:
        return "interrupted";
    case Ipopt::STOP_AT_TINY_STEP:
        return "the search direction became too small";
    case Ipopt::DIVERGING_ITERATES:
        return "the iterates diverged";
    case Ipopt::RESTORATION_FAILURE:
        return "IPOPT's feasibility restoration failed (the target may be unreachable)";
    case Ipopt::ERROR_IN_STEP_COMPUTATION:
        return "IPOPT could not compute a step";
    case Ipopt::INVALID_NUMBER_DETECTED:
        return "NaN or inf in the model's values";
    case Ipopt::TOO_FEW_DEGREES_OF_FREEDOM:
        return "too few degrees of freedom";
    default:
        return "IPOPT failed";
    }
}

class adapter final : public Ipopt::TNLP {
  public:
    adapter(const nlp& p, const solver_options& o, const vector* start, bool exact, nlp_result& out)
        : p_(p), o_(o), start_(start), exact_(exact), out_(out), jac_(p.jacobian_pattern()) {
        if (exact_) hes_ = p.hessian_pattern();
    }

    bool get_nlp_info(Index& n, Index& m, Index& nnz_jac, Index& nnz_h,
                      IndexStyleEnum& style) override {
        n = p_.variables();
        m = p_.constraints();
        nnz_jac = jac_.size();
        nnz_h = exact_ ? hes_.size() : 0;
        style = C_STYLE;
        return true;
    }
    bool get_bounds_info(Index n, Number* xl, Number* xu, Index m, Number* gl,
                         Number* gu) override {
        vector lo, hi;
        p_.bounds(lo, hi);
        for (Index i = 0; i < n; ++i) {
            xl[i] = std::isinf(lo(i)) ? -ipopt_infinity : lo(i);
            xu[i] = std::isinf(hi(i)) ? ipopt_infinity : hi(i);
        }
        p_.constraint_bounds(lo, hi);
        for (Index i = 0; i < m; ++i) {
            gl[i] = std::isinf(lo(i)) ? -ipopt_infinity : lo(i);
            gu[i] = std::isinf(hi(i)) ? ipopt_infinity : hi(i);
        }
        return true;
    }
    bool get_starting_point(Index n, bool, Number* x, bool, Number*, Number*, Index, bool,
                            Number*) override {
        const vector x0 = start_ ? *start_ : p_.start();
        if (x0.size() != n) return false;
        Eigen::Map<vector>(x, n) = x0;
        return true;
    }
    /// Whether the caller asked to stop (solver_options::stop): an evaluation then fails, which
    /// ends IPOPT's derivative test (which calls no intermediate_callback) at once.
    [[nodiscard]] bool stopping() const { return o_.stop && o_.stop(); }
    bool eval_f(Index n, const Number* x, bool, Number& f) override {
        if (stopping()) return false;
        f = p_.cost(Eigen::Map<const vector>(x, n));
        return std::isfinite(f);
    }
    bool eval_grad_f(Index n, const Number* x, bool, Number* g) override {
        if (stopping()) return false;
        p_.cost_gradient(Eigen::Map<const vector>(x, n), grad_);
        Eigen::Map<vector>(g, n) = grad_;
        return grad_.allFinite();
    }
    bool eval_g(Index n, const Number* x, bool, Index m, Number* g) override {
        if (stopping()) return false;
        p_.residual(Eigen::Map<const vector>(x, n), res_);
        Eigen::Map<vector>(g, m) = res_;
        return res_.allFinite();
    }
    bool eval_jac_g(Index n, const Number* x, bool, Index, Index nele, Index* rows, Index* cols,
                    Number* values) override {
        if (values == nullptr) {
            for (Index i = 0; i < nele; ++i) {
                rows[i] = jac_.rows[static_cast<std::size_t>(i)];
                cols[i] = jac_.cols[static_cast<std::size_t>(i)];
            }
            return true;
        }
        if (stopping()) return false;
        p_.jacobian(Eigen::Map<const vector>(x, n), buffer_);
        bool ok = true;
        for (Index i = 0; i < nele; ++i) {
            values[i] = buffer_[static_cast<std::size_t>(i)];
            ok = ok && std::isfinite(values[i]);
        }
        return ok;
    }
    bool eval_h(Index n, const Number* x, bool, Number sigma, Index m, const Number* lambda, bool,
                Index nele, Index* rows, Index* cols, Number* values) override {
        if (!exact_) return false;
        if (values == nullptr) {
            for (Index i = 0; i < nele; ++i) {
                rows[i] = hes_.rows[static_cast<std::size_t>(i)];
                cols[i] = hes_.cols[static_cast<std::size_t>(i)];
            }
            return true;
        }
        if (stopping()) return false;
        p_.hessian(Eigen::Map<const vector>(x, n), sigma, Eigen::Map<const vector>(lambda, m),
                   buffer_);
        for (Index i = 0; i < nele; ++i)
            values[i] = buffer_[static_cast<std::size_t>(i)];
        return true;
    }
    void finalize_solution(Ipopt::SolverReturn s, Index n, const Number* x, const Number*,
                           const Number*, Index m, const Number* g, const Number* lambda, Number f,
                           const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
        out_.verdict = verdict_of(s);
        out_.message = message_of(s);
        out_.x = Eigen::Map<const vector>(x, n);
        out_.lambda = Eigen::Map<const vector>(lambda, m);
        out_.cost = f;
        out_.constraint_violation = Eigen::Map<const vector>(g, m).cwiseAbs().maxCoeff();
    }
    bool intermediate_callback(Ipopt::AlgorithmMode mode, Index iter, Number f, Number inf_pr,
                               Number inf_du, Number, Number, Number, Number, Number, Index,
                               const Ipopt::IpoptData*,
                               Ipopt::IpoptCalculatedQuantities*) override {
        out_.iterations = iter;
        if (stopping()) return false;
        if (!o_.progress) return true;
        return o_.progress(iteration{.number = iter,
                                     .cost = f,
                                     .primal_infeasibility = inf_pr,
                                     .dual_infeasibility = inf_du,
                                     .restoration = mode == Ipopt::RestorationPhaseMode});
    }

  private:
    const nlp& p_;
    const solver_options& o_;
    const vector* start_;
    bool exact_;
    nlp_result& out_;
    sparsity jac_, hes_;
    vector grad_, res_;
    std::vector<double> buffer_;
};

/// Refuses a problem whose cost or equations are not finite at its starting point: a boundary
/// value or a parameter beyond what the model can evaluate (an overflow: --to 1e308, a
/// frequency of 1e200). IPOPT would fail on the first evaluation with nothing to say why.
void check_finite_start(const nlp& p, const vector& x0) {
    vector g, gradient;
    p.residual(x0, g);
    p.cost_gradient(x0, gradient);
    std::vector<double> jacobian;
    p.jacobian(x0, jacobian);
    if (std::isfinite(p.cost(x0)) && g.allFinite() && gradient.allFinite() &&
        std::all_of(jacobian.begin(), jacobian.end(), [](double v) { return std::isfinite(v); }))
        return;
    throw std::invalid_argument(
        "the problem's cost, equations or their derivatives are not finite at its starting "
        "point (the boundary states joined by a straight line): a boundary value or a model "
        "parameter too large for the model to evaluate (it overflows); check --from/--to, "
        "their velocities and the parameters");
}

/// Refuses a transcription that would not fit in memory: how many steps would.
void check_memory(const transcription& t) {
    const double have = physical_memory();
    const auto need = static_cast<double>(memory_estimate(t));
    if (!beyond_memory(need, have)) return;
    const double steps = t.problem().steps;
    const double per_step = (need - 32e6) / steps;
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "%.0f steps need about %.1f GB to optimise (an estimate: %.0f bytes a step), "
                  "more than 80 %% of this machine's %.1f GB: at most about %.0f steps fit",
                  steps, need / 1e9, per_step, have / 1e9, (0.8 * have - 32e6) / per_step);
    throw std::invalid_argument(buf);
}

/// Whether `value` is a setting IPOPT accepts for option `reg` (its type and range).
bool valid_setting(const Ipopt::RegisteredOption& reg, const std::string& value) {
    if (value.empty()) return false;
    char* end = nullptr;
    switch (reg.Type()) {
    case Ipopt::OT_Number: {
        const double v = std::strtod(value.c_str(), &end);
        return *end == '\0' && std::isfinite(v) && reg.IsValidNumberSetting(v);
    }
    case Ipopt::OT_Integer: {
        const long v = std::strtol(value.c_str(), &end, 10);
        return *end == '\0' && v >= std::numeric_limits<Index>::min() &&
               v <= std::numeric_limits<Index>::max() &&
               reg.IsValidIntegerSetting(static_cast<Index>(v));
    }
    case Ipopt::OT_String:
        return reg.IsValidStringSetting(value);
    default:
        return false;
    }
}

/// What option `reg` takes, for a message: "a number", "an integer" or its words.
std::string expected_setting(const Ipopt::RegisteredOption& reg) {
    if (reg.Type() == Ipopt::OT_Number) return "it takes a number in its range";
    if (reg.Type() == Ipopt::OT_Integer) return "it takes an integer in its range";
    std::string words;
    for (const auto& s : reg.GetValidStrings())
        words += (words.empty() ? "" : ", ") + s.value_;
    return "one of: " + words;
}

} // namespace

std::vector<ipopt_option> parse_ipopt_options(const std::string& text, const std::string& file) {
    const Ipopt::SmartPtr<Ipopt::IpoptApplication> app = new Ipopt::IpoptApplication(false);
    std::vector<ipopt_option> out;
    std::istringstream lines(text);
    std::string line;
    for (int number = 1; std::getline(lines, line); ++number) {
        std::istringstream words(line.substr(0, line.find('#')));
        ipopt_option o;
        o.line = number;
        if (!(words >> o.name)) continue;
        const auto reg = app->RegOptions()->GetOption(o.name);
        if (!Ipopt::IsValid(reg))
            throw std::invalid_argument(file + ":" + std::to_string(number) + ": '" + o.name +
                                        "' is not an IPOPT option");
        words >> o.value;
        if (!valid_setting(*reg, o.value))
            throw std::invalid_argument(file + ":" + std::to_string(number) + ": IPOPT's option '" +
                                        o.name + "' cannot be '" + o.value + "' (" +
                                        expected_setting(*reg) + ")");
        out.push_back(std::move(o));
    }
    return out;
}

std::uint64_t memory_estimate(const transcription& problem) {
    const double steps = std::max(problem.problem().steps, 1);
    const double per_step = static_cast<double>(problem.variables()) / steps;
    return static_cast<std::uint64_t>(300.0 * per_step * per_step * steps + 32e6);
}

namespace detail {

void check_solve_memory(const nlp& problem) {
    if (const auto* t = dynamic_cast<const transcription*>(&problem)) check_memory(*t);
}

nlp_result run_ipopt(const nlp& problem, const solver_options& options, const vector* start,
                     bool exact) {
    nlp_result out;
    // IPOPT's console is standard error: anything it prints (its table at a print_level the
    // options file sets, its derivative test, a rejected option) stays out of data that goes
    // to standard output.
    Ipopt::SmartPtr<Ipopt::IpoptApplication> app = new Ipopt::IpoptApplication(false);
    app->Jnlst()->AddFileJournal("console", "stderr", Ipopt::J_NONE); // Initialize sets its level
    auto& opt = *app->Options();
    opt.SetIntegerValue("print_level", options.print_level);
    opt.SetStringValue("sb", "yes"); // no banner
    opt.SetNumericValue("tol", options.tolerance);
    opt.SetNumericValue("constr_viol_tol", options.constraint_tolerance);
    opt.SetIntegerValue("max_iter", options.max_iterations);
    // IPOPT relaxes bounds by 1e-8 and projects its answer back onto them: a control at its
    // bound then moves by ~1e-8 after the equations were solved, and the trajectory no longer
    // meets them to round-off (a 1e-9 closure error measured on a bang-bang optimum). Exact
    // bounds keep the answer consistent.
    opt.SetNumericValue("bound_relax_factor", 0.0);
    opt.SetStringValue("hessian_approximation", exact ? "exact" : "limited-memory");
    // MUMPS's workspace: the factors' estimated size plus 100 %. IPOPT's default, 1000 %, has
    // every factorisation allocate and touch 11 times the estimate: on a 10-link chain at
    // N = 200, 6 times the page faults and 1.9 times the time (docs/optimal_control.md, "The
    // solver"). Short of room, IPOPT doubles it and factors again.
    opt.SetIntegerValue("mumps_mem_percent", 100);
    // MUMPS's ordering and scaling: approximate minimum degree with quasi-dense rows (6), no
    // scaling (0), where IPOPT leaves both to MUMPS (7, 77). Measured on these KKT matrices
    // (small dense blocks a step, the bound rows' slacks): the iiwa at N = 200 in 0.72 of the
    // time with gauss-2, the chains 0.72-0.97; the pendulum at N = 8000 in 1.2 times
    // (docs/optimal_control.md, "Ordering and scaling"). An options file may set them back.
    opt.SetIntegerValue("mumps_pivot_order", 6);
    opt.SetIntegerValue("mumps_scaling", 0);
    // A robot's KKT solves are refined only where the residual ratio exceeds residual_ratio_max
    // (1e-10), not at least once: the iiwa's and the chains' solves in 0.85-0.98 of the time,
    // with the same iterations and optima. IPOPT's minimum of one refinement stays for the
    // other systems: the pendulum's solves took 1.04-1.07 times as long without it, and its
    // minimum-time swing-up ran into the iteration limit (docs/optimal_control.md, "Iterative
    // refinement"). An options file may set it back.
    if (const auto* t = dynamic_cast<const transcription*>(&problem);
        t != nullptr && t->multibody())
        opt.SetIntegerValue("min_refinement_steps", 0);
    if (options.derivative_test) opt.SetStringValue("derivative_test", "first-order");
    // "": IPOPT reads no ipopt.opt from the working directory. A stray one could name an
    // output_file (truncating any file, past the tool's file checks), print into a CSV on
    // standard output, or loosen the tolerances under a "solved" verdict; our options are the
    // only ones, with the file the caller names.
    if (!options.options_file.empty()) // a regular file of at most 1 MiB, every line valid
        (void)parse_ipopt_options(
            read_input_file(options.options_file, max_ipopt_options_bytes, "IPOPT options file"),
            options.options_file);
    if (app->Initialize(options.options_file) != Ipopt::Solve_Succeeded)
        throw std::invalid_argument(
            options.options_file.empty()
                ? std::string("IPOPT could not be initialised")
                : "IPOPT rejected the options file '" + options.options_file +
                      "' (an unknown option or a value out of its range: see IPOPT's "
                      "options reference)");
    check_finite_start(problem, start != nullptr ? *start : problem.start());
    Ipopt::SmartPtr<Ipopt::TNLP> tnlp = new adapter(problem, options, start, exact, out);
    const Ipopt::ApplicationReturnStatus r = app->OptimizeTNLP(tnlp);
    if (out.x.size() == 0) { // IPOPT stopped before finalize_solution (bad problem, options)
        if (r == Ipopt::Invalid_Option)
            throw std::invalid_argument(
                "IPOPT cannot use the options it was given" +
                (options.options_file.empty() ? std::string()
                                              : " in '" + options.options_file + "'") +
                " (a linear_solver it was not built with? Debian's IPOPT has mumps)");
        // Stopped before its first iterate (a signal during its derivative test, a failed
        // evaluation): the start is the iterate reached, and nothing is claimed of it.
        out.verdict = options.stop && options.stop() ? status::interrupted : status::failed;
        out.message = "IPOPT stopped before iterating (return code " +
                      std::to_string(static_cast<int>(r)) + ")";
        out.x = start != nullptr ? *start : problem.start();
        out.lambda = vector::Zero(problem.constraints());
        out.cost = problem.cost(out.x);
        vector g;
        problem.residual(out.x, g);
        out.constraint_violation = g.size() > 0 ? g.cwiseAbs().maxCoeff() : 0.0;
    }
    return out;
}

} // namespace detail

} // namespace varsym::optimal
