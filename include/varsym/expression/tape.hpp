// varsym/expression/tape.hpp: a list of expressions of a graph compiled into straight-line code
// over doubles: each node they need, once, in topological order, one instruction each, evaluated
// by a loop over the instructions. No allocation and no call back into the graph per evaluation.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
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
    }

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
    [[nodiscard]] double output(std::size_t k) const {
        return registers_[static_cast<std::size_t>(outputs_[k])];
    }

  private:
    struct instruction {
        op kind;
        int dst, a, b; ///< registers (b: the exponent of powi)
    };
    std::vector<instruction> code_;
    std::vector<int> outputs_;
    mutable std::vector<double> registers_;
    int inputs_ = 0;
};

} // namespace varsym::expr
