// The styling language's grammar: JavaScript's precedence (?: below ||, && , equality and =~ !~, relational,
// additive, multiplicative, unary, then calls, .component and [index]), parsed by precedence climbing.
#include "sg/style/internal/StyleLexer.h"
#include "sg/style/internal/StyleProgram.h"

#include <algorithm>
#include <cmath>

namespace sg::style {

namespace {

struct BinaryOp {
    const char* text;
    Op op;
    int precedence;
};

constexpr BinaryOp kBinary[] = {
    {"||", Op::Or, 1},      {"&&", Op::And, 2}, {"===", Op::Eq, 3}, {"!==", Op::Ne, 3}, {"=~", Op::Match, 3},
    {"!~", Op::NoMatch, 3}, {"<", Op::Lt, 4},   {"<=", Op::Le, 4},  {">", Op::Gt, 4},   {">=", Op::Ge, 4},
    {"+", Op::Add, 5},      {"-", Op::Sub, 5},  {"*", Op::Mul, 6},  {"/", Op::Div, 6},  {"%", Op::Mod, 6},
};

int componentIndex(const std::string& s) {
    static const char* const kNames[] = {"x", "y", "z", "w", "r", "g", "b", "a"};
    for (int i = 0; i < 8; ++i)
        if (s == kNames[i]) return i % 4;
    return -1;
}

class Parser {
public:
    explicit Parser(Program& p) : p_(p), toks_(lexProgram(p)) {}

    void run() {
        p_.root = expression();
        if (peek().kind != TokenKind::End) p_.fail(peek().pos, "unexpected '" + peek().text + "'");
    }

private:
    const Token& peek() const { return toks_[i_]; }
    bool isPunct(const char* s) const { return peek().kind == TokenKind::Punct && peek().text == s; }
    bool accept(const char* s) {
        if (!isPunct(s)) return false;
        ++i_;
        return true;
    }
    void expect(const char* s) {
        if (!accept(s)) p_.fail(peek().pos, std::string("expected '") + s + "'");
    }

    // Adds a node, refusing trees deeper than the evaluator takes, and computes it now when all its operands
    // are constants.
    int add(Node n) {
        int h = 0;
        for (int k : {n.a, n.b, n.c})
            if (k >= 0) h = std::max<int>(h, p_.nodes[size_t(k)].height);
        bool constant = n.op != Op::Ref && n.op != Op::Const;
        for (int k : {n.a, n.b, n.c})
            if (k >= 0 && p_.nodes[size_t(k)].op != Op::Const) constant = false;
        for (int j = 0; j < n.argCount; ++j) {
            const Node& arg = p_.nodes[size_t(p_.args[size_t(n.firstArg + j)])];
            h = std::max<int>(h, arg.height);
            if (arg.op != Op::Const) constant = false;
        }
        if (h + 1 > kMaxHeight) p_.fail(n.pos, "the expression is nested too deeply");
        n.height = uint16_t(h + 1);
        p_.nodes.push_back(n);
        const int index = int(p_.nodes.size() - 1);
        if (constant) constantNode(index, evaluateNode(p_, index, EvalContext{}));
        return index;
    }

    int constantNode(int index, StyleValue v) {
        p_.constants.push_back(std::move(v));
        Node& n = p_.nodes[size_t(index)];
        n = Node{Op::Const, Fn::Color, 1, n.pos, -1, -1, -1, 0, 0, int(p_.constants.size() - 1), -1, nullptr};
        return index;
    }

    int constant(uint32_t pos, StyleValue v) {
        Node n;
        n.pos = pos;
        p_.nodes.push_back(n);
        return constantNode(int(p_.nodes.size() - 1), std::move(v));
    }

    int expression() {
        // Each nesting ((, a call's arguments, ?:) passes through here: bounds the parser's own recursion.
        if (++depth_ > kMaxHeight) p_.fail(peek().pos, "the expression is nested too deeply");
        const int cond = binary(1);
        int result = cond;
        if (isPunct("?")) {
            Node n;
            n.op = Op::Cond;
            n.pos = peek().pos;
            ++i_;
            n.a = cond;
            n.b = expression();
            expect(":");
            n.c = expression();
            result = add(n);
        }
        --depth_;
        return result;
    }

    const BinaryOp* binaryOp() const {
        if (peek().kind != TokenKind::Punct) return nullptr;
        for (const BinaryOp& b : kBinary)
            if (peek().text == b.text) return &b;
        return nullptr;
    }

    int binary(int minPrecedence) {
        int left = unary();
        for (const BinaryOp* b = binaryOp(); b && b->precedence >= minPrecedence; b = binaryOp()) {
            Node n;
            n.op = b->op;
            n.pos = peek().pos;
            ++i_;
            n.a = left;
            n.b = binary(b->precedence + 1);  // left-associative
            left = add(n);
        }
        return left;
    }

    int unary() {
        Node n;
        n.pos = peek().pos;
        if (accept("!"))
            n.op = Op::Not;
        else if (accept("-"))
            n.op = Op::Neg;
        else if (accept("+"))
            n.op = Op::Plus;
        else
            return postfix(primary());
        if (++depth_ > kMaxHeight) p_.fail(n.pos, "the expression is nested too deeply");
        n.a = unary();
        --depth_;
        return add(n);
    }

    int postfix(int node) {
        for (;;) {
            Node n;
            n.pos = peek().pos;
            n.a = node;
            if (accept("[")) {
                n.op = Op::Index;
                n.b = expression();
                expect("]");
            } else if (accept(".")) {
                if (peek().kind != TokenKind::Ident) p_.fail(peek().pos, "expected a name after '.'");
                const Token& name = toks_[i_++];
                n.pos = name.pos;
                if (isPunct("(")) return postfix(call(name, findMethod(name.text), node));
                n.op = Op::Member;
                n.value = componentIndex(name.text);
                if (n.value < 0) p_.fail(name.pos, "unknown member '" + name.text + "'");
            } else {
                return node;
            }
            node = add(n);
        }
    }

    // name(args...); a method's receiver (regExp(...).test(s)) is its first argument.
    int call(const Token& name, const FunctionInfo* f, int receiver) {
        if (!f) p_.fail(name.pos, "unknown function '" + name.text + "'");
        std::vector<int> args;
        if (receiver >= 0) args.push_back(receiver);
        expect("(");
        if (!accept(")")) {
            do args.push_back(expression());
            while (accept(","));
            expect(")");
        }
        const int n = int(args.size());
        if (n < f->minArgs || n > f->maxArgs) {
            const int off = receiver >= 0 ? 1 : 0;
            p_.fail(name.pos, name.text + " takes " + std::to_string(f->minArgs - off) +
                                  (f->maxArgs > f->minArgs ? " to " + std::to_string(f->maxArgs - off) : "") +
                                  " arguments, not " + std::to_string(n - off));
        }
        Node node;
        node.op = Op::Call;
        node.fn = f->fn;
        node.pos = name.pos;
        node.firstArg = int(p_.args.size());
        node.argCount = n;
        p_.args.insert(p_.args.end(), args.begin(), args.end());
        return add(node);
    }

    int reference(const Token& t) {
        const auto it = std::find(p_.names.begin(), p_.names.end(), t.text);
        Node n;
        n.op = Op::Ref;
        n.pos = t.pos;
        n.value = int(it - p_.names.begin());
        if (it == p_.names.end()) p_.names.push_back(t.text);
        n.slot = n.value;
        return add(n);
    }

    int identifier(const Token& t) {
        if (isPunct("(")) return call(t, findFunction(t.text), -1);
        const double inf = HUGE_VAL;
        if (t.text == "true" || t.text == "false") return constant(t.pos, StyleValue::ofBool(t.text == "true"));
        if (t.text == "null") return constant(t.pos, StyleValue::null());
        if (t.text == "undefined") return constant(t.pos, StyleValue::undefined());
        if (t.text == "NaN") return constant(t.pos, StyleValue::ofNumber(std::nan("")));
        if (t.text == "Infinity") return constant(t.pos, StyleValue::ofNumber(inf));
        if (t.text == "Math" && accept(".")) {
            const Token& c = peek();
            if (c.kind == TokenKind::Ident && (c.text == "PI" || c.text == "E")) {
                ++i_;
                return constant(t.pos, StyleValue::ofNumber(c.text == "PI" ? M_PI : M_E));
            }
            p_.fail(c.pos, "expected Math.PI or Math.E");
        }
        p_.fail(t.pos, "unknown name '" + t.text + "' (a property is ${" + t.text + "})");
    }

    int primary() {
        const Token& t = peek();
        switch (t.kind) {
            case TokenKind::Number: ++i_; return constant(t.pos, StyleValue::ofNumber(t.number));
            case TokenKind::String: ++i_; return constant(t.pos, StyleValue::ofString(t.text));
            case TokenKind::Var: ++i_; return reference(t);
            case TokenKind::Ident: ++i_; return identifier(t);
            default: break;
        }
        if (accept("(")) {
            const int e = expression();
            expect(")");
            return e;
        }
        if (isPunct("[")) p_.fail(t.pos, "array literals are not supported");
        p_.fail(t.pos, "expected an expression");
    }

    Program& p_;
    std::vector<Token> toks_;
    size_t i_ = 0;
    int depth_ = 0;
};

}  // namespace

void parseProgram(Program& p) { Parser(p).run(); }

}  // namespace sg::style
