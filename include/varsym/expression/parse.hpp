// varsym/expression/parse.hpp: reads an expression in the syntax of Python and SymPy's printer
// (numbers, names, + − * / ** or ^, parentheses, and the functions sin cos tan exp log sqrt sinh
// cosh tanh asin acos atan; the constants pi and E) into an expression graph.
//
// Precedence, as in Python: ** (right-associative, binding tighter than a unary minus on its
// left: -x**2 = −(x²), and taking a signed exponent: x**-2) above * and /, above + and −.
#pragma once

#include <cctype>
#include <charconv>
#include <functional>
#include <map>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "varsym/expression/graph.hpp"

namespace varsym::expr {

/// An expression that does not parse, or names something unknown: what() says what and where
/// (1-based column), position() is the 0-based offset into the text.
class parse_error : public std::invalid_argument {
  public:
    parse_error(const std::string& what, std::size_t position)
        : std::invalid_argument(what), position_(position) {}
    [[nodiscard]] std::size_t position() const { return position_; }

  private:
    std::size_t position_;
};

/// The functions the parser knows, by name.
inline const std::map<std::string, op, std::less<>>& functions() {
    static const std::map<std::string, op, std::less<>> table{
        {"sin", op::sin},   {"cos", op::cos},   {"tan", op::tan},   {"exp", op::exp},
        {"log", op::log},   {"sqrt", op::sqrt}, {"sinh", op::sinh}, {"cosh", op::cosh},
        {"tanh", op::tanh}, {"asin", op::asin}, {"acos", op::acos}, {"atan", op::atan}};
    return table;
}

/// How deeply parentheses, signs and powers may nest (each level is a few frames of the parser).
inline constexpr int max_depth = 256;

/// Parses `text` into g; `name` resolves a name to a node (std::nullopt: unknown). Returns the
/// expression's node. Throws parse_error.
inline int parse(std::string_view text, graph& g,
                 const std::function<std::optional<int>(std::string_view)>& name) {
    struct parser {
        std::string_view s;
        graph& g;
        const std::function<std::optional<int>(std::string_view)>& name;
        std::size_t i = 0;
        int depth = 0; ///< nesting of parentheses, signs and powers, bounded to bound the stack

        [[noreturn]] void fail(const std::string& what, std::size_t at) const {
            throw parse_error(what + " at column " + std::to_string(at + 1) + " of \"" +
                                  std::string(s) + "\"",
                              at);
        }
        void skip() {
            while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i])) != 0)
                ++i;
        }
        bool eat(std::string_view t) {
            skip();
            if (s.substr(i, t.size()) != t) return false;
            i += t.size();
            return true;
        }
        int expression() {
            int r = term();
            for (;;) {
                if (eat("+"))
                    r = g.add(r, term());
                else if (eat("-"))
                    r = g.sub(r, term());
                else
                    return r;
            }
        }
        int term() {
            int r = unary();
            for (;;) {
                if (eat("*"))
                    r = g.mul(r, unary());
                else if (eat("/"))
                    r = g.div(r, unary());
                else
                    return r;
            }
        }
        int unary() {
            if (++depth > max_depth) fail("expression nested too deeply", i);
            int r = 0;
            if (eat("-"))
                r = g.neg(unary());
            else if (eat("+"))
                r = unary();
            else
                r = power();
            --depth;
            return r;
        }
        int power() {
            const int base = primary();
            if (eat("**") || eat("^")) return g.pow(base, unary()); // right-associative
            return base;
        }
        int primary() {
            skip();
            const std::size_t at = i;
            if (i >= s.size())
                fail("expected a number, a name or '(' but the expression ended", at);
            const char c = s[i];
            if (eat("(")) {
                const int r = expression();
                if (!eat(")"))
                    fail("expected ')' to close the '(' of column " + std::to_string(at + 1), i);
                return r;
            }
            if (std::isdigit(static_cast<unsigned char>(c)) != 0 || c == '.') return number();
            if (std::isalpha(static_cast<unsigned char>(c)) != 0 || c == '_') return identifier();
            fail(std::string("unexpected '") + c + "'", at);
        }
        int number() {
            const std::size_t at = i;
            while (i < s.size() &&
                   (std::isdigit(static_cast<unsigned char>(s[i])) != 0 || s[i] == '.'))
                ++i;
            if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
                std::size_t j = i + 1;
                if (j < s.size() && (s[j] == '+' || s[j] == '-')) ++j;
                if (j < s.size() && std::isdigit(static_cast<unsigned char>(s[j])) != 0) {
                    i = j;
                    while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i])) != 0)
                        ++i;
                }
            }
            double v = 0.0;
            const auto [end, ec] = std::from_chars(s.data() + at, s.data() + i, v);
            if (ec == std::errc::result_out_of_range) fail("number out of range", at);
            if (ec != std::errc() || end != s.data() + i) fail("malformed number", at);
            return g.constant(v);
        }
        int identifier() {
            const std::size_t at = i;
            while (i < s.size() &&
                   (std::isalnum(static_cast<unsigned char>(s[i])) != 0 || s[i] == '_'))
                ++i;
            const std::string_view id = s.substr(at, i - at);
            skip();
            if (i < s.size() && s[i] == '(') {
                const auto f = functions().find(id);
                if (f == functions().end()) fail("unknown function '" + std::string(id) + "'", at);
                ++i;
                const int arg = expression();
                if (!eat(")")) fail("expected ')' after the argument of " + std::string(id), i);
                return g.call(f->second, arg);
            }
            if (const auto r = name(id)) return *r;
            if (id == "pi") return g.constant(std::numbers::pi);
            if (id == "E") return g.constant(std::numbers::e);
            if (functions().contains(id)) fail("function '" + std::string(id) + "' needs '('", at);
            fail("unknown name '" + std::string(id) + "'", at);
        }
    };
    parser p{text, g, name};
    const int r = p.expression();
    p.skip();
    if (p.i < text.size()) p.fail(std::string("unexpected '") + text[p.i] + "'", p.i);
    return r;
}

} // namespace varsym::expr
