#pragma once

#include <memory>
#include <string>

namespace cc::bench {

/// Bullet 3's btSoftBody cloth on the benchmark scene (BenchScenes.h), set up as Bullet's own cloth
/// demos do: btSoftBodyHelpers::CreatePatch with shear diagonals, default btSoftBody::Config (one
/// position-solver iteration, link stiffness 1, no damping), generateBendingConstraints(2),
/// setTotalMass(0.15 kg), in a btSoftRigidDynamicsWorld without rigid bodies. Bullet is a peer to
/// compare against, never a crowdcloth dependency: its types stay inside BulletPeer.cpp.
/// Single-threaded (Bullet's default soft-body solver has no threading).
class BulletPatch {
public:
    /// `vertices` per side, >= 2. `positionIterations` > 0 overrides m_cfg.piterations (Bullet's
    /// default is 1), to see what Bullet's step costs when iterated toward a stiffer cloth.
    explicit BulletPatch(int vertices, int positionIterations = 0);
    ~BulletPatch();
    BulletPatch(const BulletPatch&) = delete;
    BulletPatch& operator=(const BulletPatch&) = delete;

    /// Advances by kDt as exactly one internal Bullet step; returns the internal steps taken (1).
    int step();

    int vertexCount() const;
    /// Largest (length / rest length - 1) over the mesh edges: the links between grid neighbours
    /// plus each square's triangulation diagonal, i.e. all links except the bending ones. This is
    /// the edge set ClothSimulation::maxEdgeStrain() measures on our 4-8 mesh.
    double maxEdgeStrain() const;
    /// [m] lowest node y.
    double lowestY() const;

private:
    struct World;
    std::unique_ptr<World> mWorld;
};

/// The linked Bullet's version and btScalar precision, e.g. "Bullet 3.24, btScalar = float".
std::string bulletDescription();

} // namespace cc::bench
