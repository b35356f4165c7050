//! The lattice model in the formulations (docs/physics.md §9.8).

use floebench::fracture::lattice::percussion::Impact;
use floebench::fracture::lattice::Lattice;
use floebench::fracture::strike::{chain_options, lattice_spec, strike};
use floebench::geometry::Vec2;
use floebench::model::fracture::{FractureModel, FractureSettings};
use floebench::model::{Floe, FloeOrigin};

fn diamond() -> Floe {
    let poly = [
        Vec2::new(0.0, 5.0),
        Vec2::new(5.0, 0.0),
        Vec2::new(10.0, 5.0),
        Vec2::new(5.0, 10.0),
    ];
    Floe::from_world_polygon(&poly, 1.0, 917.0, Vec2::zeros(), 0.0, FloeOrigin::Listed(0))
}

#[test]
fn explore() {
    let f = diamond();
    let s = FractureSettings {
        model: FractureModel::Lattice,
        min_area: 1.0,
        spacing: Some(0.5),
        ..FractureSettings::default()
    };
    let l = Lattice::build(&f.shape, lattice_spec(&s, &f)).unwrap();
    println!("nodes {}", l.nodes.len());
    for v in [0.3, 0.6, 1.0, 2.0, 3.0] {
        let imp = Impact {
            point: Vec2::new(5.0, 0.0),
            normal: Vec2::new(-1.0, 0.0),
            mass: f64::INFINITY,
            speed: v,
        };
        let mut p = floebench::fracture::lattice::percussion::Percussion::new(&l, Default::default(), imp, chain_options(&s)).unwrap();
        let oo = p.run();
        println!("  broken {} frags {:?} area err {}", oo.broken.len(), oo.fragments.iter().map(|f| (f.nodes.len(), (f.mass/917.0) as i64)).collect::<Vec<_>>(), oo.hull_area_error);
        let o = strike(&l, imp, chain_options(&s), true, s.min_area, 917.0).unwrap();
        println!(
            "{v}: bound {} weakest {} pieces {:?}",
            o.bound,
            o.weakest,
            o.split.map(|x| (x.broken, x.pieces.iter().map(|p| p.mass).collect::<Vec<_>>()))
        );
    }
}
