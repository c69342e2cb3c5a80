#pragma once
/// @file geovoronoi.hpp
/// @brief Everything of the core library and its sequential backend.

#include <geovoronoi/backend/seq.hpp>
#include <geovoronoi/branching_grid.hpp>
#include <geovoronoi/branching_shape.hpp>
#include <geovoronoi/config.hpp>
#include <geovoronoi/connectivity.hpp>
#include <geovoronoi/error.hpp>
#include <geovoronoi/grid.hpp>
#include <geovoronoi/image.hpp>
#include <geovoronoi/metric.hpp>
#include <geovoronoi/phantom.hpp>
#include <geovoronoi/policy.hpp>
#include <geovoronoi/precision.hpp>
#include <geovoronoi/problem.hpp>
#include <geovoronoi/result.hpp>
#include <geovoronoi/shape_functions.hpp>
#include <geovoronoi/shape_update.hpp>
#include <geovoronoi/update.hpp>
#include <geovoronoi/voronoi.hpp>
#include <geovoronoi/voxelize.hpp>
