#include "Shapes.h"

namespace {
struct Square : Shape {
    explicit Square(int side) : side(side) {}
    int area() const override { return side * side; }
    std::string name() const override { return "square " + std::to_string(side); }
    int side;
};
struct Rect : Shape {
    Rect(int w, int h) : w(w), h(h) {}
    int area() const override { return w * h; }
    std::string name() const override { return "rect " + std::to_string(w) + "x" + std::to_string(h); }
    int w, h;
};
}  // namespace

std::vector<std::unique_ptr<Shape>> make_shapes()
{
    std::vector<std::unique_ptr<Shape>> shapes;
    shapes.push_back(std::make_unique<Square>(3));
    shapes.push_back(std::unique_ptr<Shape>(new Rect(2, 5)));
    return shapes;
}
