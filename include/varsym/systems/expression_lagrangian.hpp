// varsym/systems/expression_lagrangian.hpp: a Lagrangian L(q, q̇, t) given at run time as an
// expression over named coordinates, their velocities and parameters, e.g.
//     "0.5*m*l**2*th_dot**2 + m*g*l*cos(th)"   coordinates {th}, parameters {m=1, g=9.81, l=1}.
// Its first and second derivatives are differentiated symbolically once, when it is made; all of
// them are then compiled into straight-line code over doubles (expression/tape.hpp). A step
// evaluates that code: no parsing, no allocation, no call back into the caller.
//
// Names: each coordinate x has the velocity x_dot; t is the time (no coordinate or parameter
// may be called t); pi and E are the constants; parameters are numbers fixed when the
// Lagrangian is made. The syntax is Python's (expression/parse.hpp), so str() of a SymPy
// expression in these symbols parses.
#pragma once

#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "varsym/expression/tape.hpp"
#include "varsym/expression/variables.hpp"
#include "varsym/systems/lagrangian.hpp"

namespace varsym {

class expression_lagrangian {
  public:
    static constexpr int dim = dynamic;

    /// Parses `text` over `coordinates` (their velocities: name_dot) and `parameters`. Throws
    /// expr::parse_error (what() names the column) for an expression that does not parse or
    /// names something unknown, std::invalid_argument for bad or repeated names.
    expression_lagrangian(std::string text, std::vector<std::string> coordinates,
                          std::vector<expression_parameter> parameters = {})
        : text_(std::move(text)), vars_(std::move(coordinates), std::move(parameters)) {
        const int d = dimension();
        expr::graph g;
        const int l = vars_.parse(text_, g);
        // Autonomous where ∂L/∂t simplifies to zero (t * 0, t - t), whatever the text names.
        time_dependent_ = vars_.uses_time() && !g.is(g.derivative(l, 2 * d), 0.0);
        // Outputs: L; ∂L/∂q, ∂L/∂q̇; then ∂²L/∂q∂q (i ≤ j), ∂²L/∂q∂q̇ (all), ∂²L/∂q̇∂q̇ (i ≤ j).
        std::vector<int> out{l}, lq(static_cast<std::size_t>(d)), lv(static_cast<std::size_t>(d));
        for (int i = 0; i < d; ++i) {
            lq[static_cast<std::size_t>(i)] = g.derivative(l, i);
            lv[static_cast<std::size_t>(i)] = g.derivative(l, d + i);
        }
        out.insert(out.end(), lq.begin(), lq.end());
        out.insert(out.end(), lv.begin(), lv.end());
        value_ = expr::tape(g, {l}, vars_.inputs());
        gradient_ = expr::tape(g, out, vars_.inputs());
        for (int i = 0; i < d; ++i)
            for (int j = i; j < d; ++j)
                out.push_back(g.derivative(lq[static_cast<std::size_t>(i)], j));
        for (int i = 0; i < d; ++i)
            for (int j = 0; j < d; ++j)
                out.push_back(g.derivative(lq[static_cast<std::size_t>(i)], d + j));
        for (int i = 0; i < d; ++i)
            for (int j = i; j < d; ++j)
                out.push_back(g.derivative(lv[static_cast<std::size_t>(i)], d + j));
        all_ = expr::tape(g, out, vars_.inputs());
        if (time_dependent_) time_rate_ = expr::tape(g, {g.derivative(l, 2 * d)}, vars_.inputs());
        input_.assign(static_cast<std::size_t>(vars_.inputs()), 0.0);
        find_separable(g, lq, out);
    }

    [[nodiscard]] int dimension() const { return vars_.dimension(); }
    [[nodiscard]] const std::string& text() const { return text_; }
    [[nodiscard]] const std::vector<std::string>& coordinates() const {
        return vars_.coordinates();
    }
    [[nodiscard]] const std::vector<expression_parameter>& parameters() const {
        return vars_.parameters();
    }
    /// Whether L depends on the time t (its energy is then not conserved): whether ∂L/∂t is not
    /// identically zero once simplified, not merely whether the text names t.
    [[nodiscard]] bool depends_on_time() const { return time_dependent_; }
    /// ∂L/∂t at (q, q̇, t); 0 for an L that does not depend on time. The general engine sums it
    /// over each step's quadrature points into the energy balance (schemes/variational.hpp).
    [[nodiscard]] double time_derivative(const vec<dynamic>& q, const vec<dynamic>& v,
                                         double t) const {
        if (!time_dependent_) return 0.0;
        time_rate_.run(load(q, v, t));
        return time_rate_.output(0);
    }
    /// Whether L = ½ q̇ᵀ M q̇ − V(q) with a constant M (decided symbolically: ∂²L/∂q̇² constant,
    /// ∂²L/∂q∂q̇ ≡ 0, no term linear in q̇, no t): then the separable steppers (the paper's
    /// Simpson, Newmark, the family) can run it, faster than the general engine.
    [[nodiscard]] bool separable() const { return separable_; }
    /// M, where separable().
    [[nodiscard]] const mat<dynamic>& separable_mass() const { return mass_; }
    /// V(q) = −L(q, 0), ∇V and ∇²V, where separable() (straight-line code of its own).
    [[nodiscard]] double potential(const vec<dynamic>& q) const {
        value_.run(load_position(q));
        return -value_.output(0);
    }
    [[nodiscard]] vec<dynamic> potential_gradient(const vec<dynamic>& q) const {
        vec<dynamic> g(dimension());
        potential_gradient(load_position(q).data(), g.data());
        return g;
    }
    /// ∇V(q) into g[0 … d) and ∇²V(q) into h[0 … d²) (column-major), q[0 … d): the separable
    /// steppers' hot path, no check and no allocation. V's own code reads q̇ and t as 0, and is
    /// only ever run here, so that only the positions are loaded.
    void potential_gradient(const double* q, double* g) const {
        const int d = dimension();
        potential_gradient_.run_prefix(q, d);
        for (int i = 0; i < d; ++i)
            g[i] = potential_gradient_.output(static_cast<std::size_t>(i));
    }
    /// ∇V at `count` points at once: point j at q[j d … j d + d), its gradient into g[j d …
    /// j d + d). The same values as potential_gradient's, bit for bit, for less dispatch.
    void potential_gradients(const double* q, int count, double* g) const {
        const int d = dimension();
        potential_gradient_.run_batch(q, d, count, g);
    }
    void potential_hessian(const double* q, double* h) const {
        const int d = dimension();
        potential_hessian_.run_prefix(q, d);
        std::size_t k = 0;
        for (int i = 0; i < d; ++i)
            for (int j = i; j < d; ++j)
                h[i + j * d] = h[j + i * d] = potential_hessian_.output(k++);
    }
    /// ∇V(q) into g and ∇²V(q) into h (as above) by one code, their common terms once: the same
    /// values as potential_gradient's and potential_hessian's, bit for bit.
    void potential_gradient_and_hessian(const double* q, double* g, double* h) const {
        const int d = dimension();
        potential_derivatives_.run_prefix(q, d);
        std::size_t k = 0;
        for (int i = 0; i < d; ++i)
            g[i] = potential_derivatives_.output(k++);
        for (int i = 0; i < d; ++i)
            for (int j = i; j < d; ++j)
                h[i + j * d] = h[j + i * d] = potential_derivatives_.output(k++);
    }
    [[nodiscard]] mat<dynamic> potential_hessian(const vec<dynamic>& q) const {
        mat<dynamic> h(dimension(), dimension());
        potential_hessian(load_position(q).data(), h.data());
        return h;
    }
    /// The length of the compiled code of L and all its derivatives (instructions).
    [[nodiscard]] std::size_t instructions() const { return all_.instructions(); }

    [[nodiscard]] double operator()(const vec<dynamic>& q, const vec<dynamic>& v, double t) const {
        value_.run(load(q, v, t));
        return value_.output(0);
    }
    void gradient(const vec<dynamic>& q, const vec<dynamic>& v, double t,
                  lagrangian_terms<dynamic>& terms) const {
        const int d = dimension();
        gradient_.run(load(q, v, t));
        terms.value = gradient_.output(0);
        terms.lq.resize(d);
        terms.lv.resize(d);
        for (int i = 0; i < d; ++i) {
            terms.lq(i) = gradient_.output(static_cast<std::size_t>(1 + i));
            terms.lv(i) = gradient_.output(static_cast<std::size_t>(1 + d + i));
        }
    }
    void derivatives(const vec<dynamic>& q, const vec<dynamic>& v, double t,
                     lagrangian_terms<dynamic>& terms) const {
        const int d = dimension();
        all_.run(load(q, v, t));
        std::size_t k = 0;
        terms.value = all_.output(k++);
        terms.lq.resize(d);
        terms.lv.resize(d);
        terms.lqq.resize(d, d);
        terms.lqv.resize(d, d);
        terms.lvv.resize(d, d);
        for (int i = 0; i < d; ++i)
            terms.lq(i) = all_.output(k++);
        for (int i = 0; i < d; ++i)
            terms.lv(i) = all_.output(k++);
        for (int i = 0; i < d; ++i)
            for (int j = i; j < d; ++j)
                terms.lqq(i, j) = terms.lqq(j, i) = all_.output(k++);
        for (int i = 0; i < d; ++i)
            for (int j = 0; j < d; ++j)
                terms.lqv(i, j) = all_.output(k++);
        for (int i = 0; i < d; ++i)
            for (int j = i; j < d; ++j)
                terms.lvv(i, j) = terms.lvv(j, i) = all_.output(k++);
    }

    /// The Hessian in z = (q, q̇) (2d square) of aᵀ ∂L/∂q + bᵀ ∂L/∂q̇ at (q, q̇, t): L's third
    /// derivatives contracted with (a, b), which an optimal control transcription's exact
    /// Hessian needs. Exact: the rates of the symbolic second derivatives' code along (a, b)
    /// (forward-mode differentiation of that code, tape::run_tangent), one pass over it.
    void third(const vec<dynamic>& q, const vec<dynamic>& v, double t, const vec<dynamic>& a,
               const vec<dynamic>& b, mat<dynamic>& out) const {
        const int d = dimension();
        const std::span<const double> in = load(q, v, t);
        direction_.assign(in.size(), 0.0);
        for (int i = 0; i < d; ++i) {
            direction_[static_cast<std::size_t>(i)] = a(i);
            direction_[static_cast<std::size_t>(d + i)] = b(i);
        }
        all_.run_tangent(in.data(), direction_.data(), static_cast<int>(in.size()));
        out.resize(2 * d, 2 * d);
        std::size_t k = static_cast<std::size_t>(1 + 2 * d); // past L, L_q, L_q̇
        for (int i = 0; i < d; ++i)
            for (int j = i; j < d; ++j)
                out(i, j) = out(j, i) = all_.tangent(k++);
        for (int i = 0; i < d; ++i)
            for (int j = 0; j < d; ++j)
                out(i, d + j) = out(d + j, i) = all_.tangent(k++);
        for (int i = 0; i < d; ++i)
            for (int j = i; j < d; ++j)
                out(d + i, d + j) = out(d + j, d + i) = all_.tangent(k++);
    }

  private:
    /// Sets separable_, mass_ and potential_ from the graph: `out` holds L, L_q, L_v, then
    /// L_qq (i ≤ j), L_qv (all), L_vv (i ≤ j), as the constructor laid them out.
    void find_separable(expr::graph& g, const std::vector<int>& lq, const std::vector<int>& out) {
        const int d = dimension();
        if (time_dependent_) return;
        const std::size_t n_qq = static_cast<std::size_t>(d * (d + 1) / 2);
        const std::size_t qv = static_cast<std::size_t>(1 + 2 * d) + n_qq;
        const std::size_t vv = qv + static_cast<std::size_t>(d * d);
        for (std::size_t k = qv; k < vv; ++k)
            if (!g.is(out[k], 0.0)) return;
        mass_.resize(d, d);
        std::size_t k = vv;
        for (int i = 0; i < d; ++i)
            for (int j = i; j < d; ++j, ++k) {
                if (!g.is_constant(out[k])) return;
                mass_(i, j) = mass_(j, i) = g[out[k]].value;
            }
        // L_q̇ = M q̇ + a with a constant (L_vv constant, L_qv = 0): a term aᵀq̇ changes p, so
        // it must be absent. Its value at any point is a; take q = 1, q̇ = 0.
        gradient_.run(load(vec<dynamic>::Ones(d), vec<dynamic>::Zero(d), 0.0));
        for (int i = 0; i < d; ++i)
            if (gradient_.output(static_cast<std::size_t>(1 + d + i)) != 0.0) return;
        const Eigen::LLT<mat<dynamic>> llt(mass_);
        if (llt.info() != Eigen::Success) return; // not positive definite: the general engine
        // ∇V and ∇²V each by its own code (a step asks for gradients far more often), and both
        // by one (Newton's stage iterations ask for both at one point). Their outputs are
        // ∇V = −L_q and ∇²V = −L_qq, built in the graph, where −(−x) = x removes the negations
        // the rules for − and / leave.
        std::vector<int> grad, hess;
        for (const int i : lq)
            grad.push_back(g.neg(i));
        for (auto i = out.begin() + 1 + 2 * d; i != out.begin() + static_cast<std::ptrdiff_t>(qv);
             ++i)
            hess.push_back(g.neg(*i));
        potential_gradient_ = expr::tape(g, grad, vars_.inputs());
        potential_hessian_ = expr::tape(g, hess, vars_.inputs());
        grad.insert(grad.end(), hess.begin(), hess.end());
        potential_derivatives_ = expr::tape(g, grad, vars_.inputs());
        separable_ = true;
    }

    /// q with q̇ = 0 and t = 0 (for V(q) = −L(q, 0)): the inputs past q stay 0.
    std::span<const double> load_position(const vec<dynamic>& q) const {
        const int d = dimension();
        if (q.size() != d)
            throw std::invalid_argument("q must have " + std::to_string(d) +
                                        " entries, one per coordinate");
        position_input_.resize(static_cast<std::size_t>(vars_.inputs()), 0.0);
        for (int i = 0; i < d; ++i)
            position_input_[static_cast<std::size_t>(i)] = q(i);
        return position_input_;
    }

    std::span<const double> load(const vec<dynamic>& q, const vec<dynamic>& v, double t) const {
        vars_.load(q, v, t, input_);
        return input_;
    }

    std::string text_;
    expr::variables vars_;
    expr::tape value_, gradient_, all_, time_rate_, potential_gradient_, potential_hessian_,
        potential_derivatives_;
    mutable std::vector<double> input_, position_input_, direction_;
    bool time_dependent_ = false, separable_ = false;
    mat<dynamic> mass_;
};

} // namespace varsym
