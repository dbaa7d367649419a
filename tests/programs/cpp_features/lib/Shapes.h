#ifndef SHAPES_H
#define SHAPES_H
#include <memory>
#include <string>
#include <vector>

struct Shape {
    virtual ~Shape() = default;
    virtual int area() const = 0;
    virtual std::string name() const = 0;
};

std::vector<std::unique_ptr<Shape>> make_shapes();

template <typename T>
T total(const std::vector<T>& values)
{
    T sum{};
    for (const T& v : values)
        sum += v;
    return sum;
}
#endif
