// Any hal::PlantModel behind one type, so that one host loop (`lashid hil`'s plant peer) and one host board type
// play a built-in scenario's plant or a plant file's alike.
#pragma once

#include <concepts>
#include <memory>
#include <type_traits>
#include <utility>

#include "lashid/hal/plant_model.hpp"

namespace lashid::sim {

class AnyPlant {
 public:
  template <hal::PlantModel P>
    requires(!std::same_as<std::remove_cvref_t<P>, AnyPlant>)
  explicit AnyPlant(P plant) : model_(std::make_unique<Model<P>>(std::move(plant))) {}

  double step(double v) { return model_->step(v); }

 private:
  struct Interface {
    virtual ~Interface() = default;
    virtual double step(double v) = 0;
  };
  template <class P>
  struct Model final : Interface {
    explicit Model(P p) : plant(std::move(p)) {}
    double step(double v) override { return plant.step(v); }
    P plant;
  };
  std::unique_ptr<Interface> model_;
};

static_assert(hal::PlantModel<AnyPlant>);

}  // namespace lashid::sim
