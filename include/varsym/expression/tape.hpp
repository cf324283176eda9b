// varsym/expression/tape.hpp: a list of expressions of a graph compiled into straight-line code
// over doubles: each node they need, once, in topological order, one instruction each, evaluated
// by a loop over the instructions. No allocation and no call back into the graph per evaluation.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <vector>

#include "varsym/expression/graph.hpp"

namespace varsym::expr {

class tape {
  public:
    tape() = default;
    /// Compiles `outputs` of g for inputs 0 … inputs − 1.
    tape(const graph& g, const std::vector<int>& outputs, int inputs) {
        const int n = g.size();
        std::vector<char> needed(static_cast<std::size_t>(n), 0);
        for (const int o : outputs)
            needed[static_cast<std::size_t>(o)] = 1;
        for (int id = n - 1; id >= 0; --id) { // children have smaller ids than parents
            if (needed[static_cast<std::size_t>(id)] == 0) continue;
            const node& x = g[id];
            if (x.a >= 0) needed[static_cast<std::size_t>(x.a)] = 1;
            if (x.b >= 0 && x.kind != op::powi) needed[static_cast<std::size_t>(x.b)] = 1;
        }
        // Registers: the inputs first, then the constants and results the outputs need.
        std::vector<int> reg(static_cast<std::size_t>(n), -1);
        registers_.assign(static_cast<std::size_t>(inputs), 0.0);
        for (int id = 0; id < n; ++id) {
            if (needed[static_cast<std::size_t>(id)] == 0) continue;
            const node& x = g[id];
            if (x.kind == op::input) {
                reg[static_cast<std::size_t>(id)] = static_cast<int>(x.value);
                continue;
            }
            const int r = static_cast<int>(registers_.size());
            reg[static_cast<std::size_t>(id)] = r;
            registers_.push_back(x.kind == op::constant ? x.value : 0.0);
            if (x.kind == op::constant) continue;
            instruction in{x.kind, r, reg[static_cast<std::size_t>(x.a)], -1};
            if (x.kind == op::powi)
                in.b = static_cast<int>(x.value);
            else if (x.b >= 0)
                in.b = reg[static_cast<std::size_t>(x.b)];
            code_.push_back(in);
        }
        for (const int o : outputs)
            outputs_.push_back(reg[static_cast<std::size_t>(o)]);
        inputs_ = inputs;
        lanes_.assign(registers_.size() * lanes, 0.0);
        for (std::size_t k = 0; k < registers_.size(); ++k)
            std::fill_n(lanes_.begin() + static_cast<std::ptrdiff_t>(k * lanes), lanes,
                        registers_[k]);
    }

    /// How many input sets run_batch evaluates per pass over the instructions (measured on the
    /// family's Kepler steps: 4 beat 2 and 8, docs/python.md).
    static constexpr int lanes = 4;

    [[nodiscard]] int inputs() const { return inputs_; }
    [[nodiscard]] std::size_t outputs() const { return outputs_.size(); }
    [[nodiscard]] std::size_t instructions() const { return code_.size(); }

    /// Evaluates with these inputs (inputs() of them); output(k) reads the k-th result. Not for
    /// concurrent use of one tape (its registers are its own): copy it per thread.
    void run(std::span<const double> in) const { run_prefix(in.data(), inputs_); }
    /// Evaluates with inputs 0 … n − 1 from `in` (n ≤ inputs()); the inputs past n keep the
    /// values the last run gave them (0 for a tape never run with them).
    void run_prefix(const double* in, int n) const {
        double* r = registers_.data();
        for (int k = 0; k < n; ++k)
            r[k] = in[k];
        for (const instruction& i : code_) {
            const double a = r[i.a];
            switch (i.kind) {
            case op::add:
                r[i.dst] = a + r[i.b];
                break;
            case op::sub:
                r[i.dst] = a - r[i.b];
                break;
            case op::mul:
                r[i.dst] = a * r[i.b];
                break;
            case op::div:
                r[i.dst] = a / r[i.b];
                break;
            case op::neg:
                r[i.dst] = -a;
                break;
            case op::square:
                r[i.dst] = a * a;
                break;
            case op::powi:
                r[i.dst] = integer_power(a, i.b);
                break;
            case op::pow:
                r[i.dst] = std::pow(a, r[i.b]);
                break;
            case op::sin:
                r[i.dst] = std::sin(a);
                break;
            case op::cos:
                r[i.dst] = std::cos(a);
                break;
            case op::sqrt: // distances: in most potentials
                r[i.dst] = std::sqrt(a);
                break;
            default:
                r[i.dst] = apply(i.kind, a);
                break;
            }
        }
    }
    /// Evaluates `count` input sets, set j's inputs 0 … n − 1 at in[j · n + i] (n ≤ inputs();
    /// those past n are 0), and writes set j's outputs to out[j · outputs() + k]. Each set goes
    /// through the same operations in the same order as in run_prefix, so the results are those
    /// of run_prefix bit for bit; the dispatch on the instruction is paid once per `lanes` sets,
    /// whose operations run side by side (the family stepper's points of a sweep).
    void run_batch(const double* in, int n, int count, double* out) const {
        for (int first = 0; first < count;) {
            const int sets = count - first;
            if (sets >= 3) // a last chunk of 3 repeats a set; one of 1 or 2 takes two lanes
                first += run_chunk<lanes>(in, n, first, std::min(lanes, sets), out);
            else
                first += run_chunk<2>(in, n, first, sets, out);
        }
    }
    [[nodiscard]] double output(std::size_t k) const {
        return registers_[static_cast<std::size_t>(outputs_[k])];
    }

    /// run_prefix with each register's derivative along a direction of the inputs: input k
    /// moves at rate din[k] (k < n; the inputs past n at rate 0), and tangent(k) reads the k-th
    /// output's rate, exact (forward-mode differentiation of the straight-line code, one
    /// direction: ∂/∂ε of the outputs at in + ε din). output(k) reads the values as after run.
    void run_tangent(const double* in, const double* din, int n) const {
        run_prefix(in, n);
        tangents_.assign(registers_.size(), 0.0);
        double* t = tangents_.data();
        const double* r = registers_.data();
        for (int k = 0; k < n; ++k)
            t[k] = din[k];
        for (const instruction& i : code_)
            t[i.dst] = rate(i, r, t);
    }
    [[nodiscard]] double tangent(std::size_t k) const {
        return tangents_[static_cast<std::size_t>(outputs_[k])];
    }

  private:
    struct instruction {
        op kind;
        int dst, a, b; ///< registers (b: the exponent of powi)
    };

    /// The rate of instruction i's result from its operands' values r and rates t (the chain
    /// rule of each operation; r[i.dst] holds the result).
    static double rate(const instruction& i, const double* r, const double* t) {
        const double a = r[i.a], da = t[i.a], y = r[i.dst];
        switch (i.kind) {
        case op::add:
            return da + t[i.b];
        case op::sub:
            return da - t[i.b];
        case op::mul:
            return da * r[i.b] + a * t[i.b];
        case op::div:
            return (da - y * t[i.b]) / r[i.b];
        case op::neg:
            return -da;
        case op::square:
            return 2.0 * a * da;
        case op::powi:
            return i.b == 0 ? 0.0 : i.b * integer_power(a, i.b - 1) * da;
        case op::pow: { // a^b: b a^(b−1) da + a^b log(a) db (the second only where b moves)
            const double b = r[i.b], db = t[i.b];
            return b * std::pow(a, b - 1.0) * da + (db == 0.0 ? 0.0 : y * std::log(a) * db);
        }
        case op::sin:
            return std::cos(a) * da;
        case op::cos:
            return -std::sin(a) * da;
        case op::tan:
            return (1.0 + y * y) * da;
        case op::exp:
            return y * da;
        case op::log:
            return da / a;
        case op::sqrt:
            return da / (2.0 * y);
        case op::sinh:
            return std::cosh(a) * da;
        case op::cosh:
            return std::sinh(a) * da;
        case op::tanh:
            return (1.0 - y * y) * da;
        case op::asin:
            return da / std::sqrt(1.0 - a * a);
        case op::acos:
            return -da / std::sqrt(1.0 - a * a);
        case op::atan:
            return da / (1.0 + a * a);
        default:
            throw std::logic_error("varsym::expr::tape: no rate for this operation");
        }
    }

    /// Sets first … first + sets − 1 (sets ≤ width) through the code side by side (an unused
    /// lane repeats the last set), their outputs into out; returns sets.
    template <int width>
    int run_chunk(const double* in, int n, int first, int sets, double* out) const {
        double* r = lanes_.data();
        for (int k = 0; k < n; ++k)
            for (int j = 0; j < width; ++j)
                r[k * lanes + j] = in[(first + std::min(j, sets - 1)) * n + k];
        for (const instruction& i : code_)
            run_lanes<width>(i, r);
        const std::size_t m = outputs_.size();
        for (int j = 0; j < sets; ++j)
            for (std::size_t k = 0; k < m; ++k)
                out[static_cast<std::size_t>(first + j) * m + k] =
                    r[static_cast<std::size_t>(outputs_[k]) * lanes + static_cast<std::size_t>(j)];
        return sets;
    }

    /// One instruction on the first `width` lanes. dst is never an operand: the pointers do not
    /// alias, which lets the loops compile to packed operations.
    template <int width>
    [[gnu::always_inline]] static void run_lanes(const instruction& i, double* r) {
        double* __restrict o = r + i.dst * lanes;
        const double* __restrict a = r + i.a * lanes;
        const auto second = [&] { return r + i.b * lanes; }; // the binary operations' b
        switch (i.kind) {
        case op::add:
            for (int j = 0; j < width; ++j)
                o[j] = a[j] + second()[j];
            break;
        case op::sub:
            for (int j = 0; j < width; ++j)
                o[j] = a[j] - second()[j];
            break;
        case op::mul:
            for (int j = 0; j < width; ++j)
                o[j] = a[j] * second()[j];
            break;
        case op::div:
            for (int j = 0; j < width; ++j)
                o[j] = a[j] / second()[j];
            break;
        case op::pow:
            for (int j = 0; j < width; ++j)
                o[j] = std::pow(a[j], second()[j]);
            break;
        case op::square:
            for (int j = 0; j < width; ++j)
                o[j] = a[j] * a[j];
            break;
        case op::neg:
            for (int j = 0; j < width; ++j)
                o[j] = -a[j];
            break;
        case op::sqrt:
            for (int j = 0; j < width; ++j)
                o[j] = std::sqrt(a[j]);
            break;
        case op::powi:
            for (int j = 0; j < width; ++j)
                o[j] = integer_power(a[j], i.b);
            break;
        default:
            for (int j = 0; j < width; ++j)
                o[j] = apply(i.kind, a[j]);
            break;
        }
    }

    std::vector<instruction> code_;
    std::vector<int> outputs_;
    mutable std::vector<double> registers_, lanes_,
        tangents_; ///< lanes_: register k of set j at k·lanes + j
    int inputs_ = 0;
};

} // namespace varsym::expr
