#ifndef ACCELCAL_RESIDUALS_SCALAR_BLOCKS_H_
#define ACCELCAL_RESIDUALS_SCALAR_BLOCKS_H_

// Residuals whose parameters are a list of catalogue parameters (models/effects.h), one
// scalar Ceres block each, so that the list can follow the registered effects
// (models/effect_list.h) instead of being spelled out in each functor's signature.
//
// Ceres calls an autodiff functor as f(block_0, ..., block_{N-1}, residuals). Such a
// functor declares
//
//   template <typename T, typename... Rest>
//   bool operator()(const T* const first, Rest... rest) const {
//     ModelParameters<T> parameters;
//     T* residuals = GatherParameters(layout_, &parameters, first, rest...);
//
// and its cost function is ScalarBlocksCostFunction<Functor, kResiduals, N>. Each block
// keeps its own name, so ceres::Covariance answers per parameter and a parameter is held
// constant with SetParameterBlockConstant, as with hand-written blocks; the Jet has one
// dual part per block, as it would with hand-written ones.

#include <ceres/autodiff_cost_function.h>

#include <array>
#include <tuple>
#include <utility>

#include "models/effects.h"

namespace accelcal {
namespace internal {

template <typename Functor, int kResiduals, int... kIndices>
ceres::AutoDiffCostFunction<Functor, kResiduals, (kIndices * 0 + 1)...> ScalarBlocksCost(
    std::integer_sequence<int, kIndices...>);

template <typename T, size_t N, typename Tuple, size_t... kIndices>
void Gather(const std::array<Parameter, N>& layout, const Tuple& arguments,
            ModelParameters<T>* parameters, std::index_sequence<kIndices...>) {
  (((*parameters)[layout[kIndices]] = std::get<kIndices>(arguments)[0]), ...);
}

}  // namespace internal

// An AutoDiffCostFunction with kBlocks parameter blocks of size 1.
template <typename Functor, int kResiduals, int kBlocks>
using ScalarBlocksCostFunction = decltype(internal::ScalarBlocksCost<Functor, kResiduals>(
    std::make_integer_sequence<int, kBlocks>()));

// Copies the N scalar blocks of a functor call into `parameters` at the places `layout`
// names (the others keep their values) and returns the call's residual pointer.
template <typename T, size_t N, typename... Arguments>
T* GatherParameters(const std::array<Parameter, N>& layout, ModelParameters<T>* parameters,
                    const Arguments&... arguments) {
  static_assert(sizeof...(Arguments) == N + 1, "one pointer per block, then the residuals");
  const auto all = std::make_tuple(arguments...);
  internal::Gather(layout, all, parameters, std::make_index_sequence<N>());
  return std::get<N>(all);
}

}  // namespace accelcal

#endif  // ACCELCAL_RESIDUALS_SCALAR_BLOCKS_H_
