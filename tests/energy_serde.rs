//! `AnyEnergy` deserialization: `law` tag, validated parameters, unknown fields rejected.

use celltissue::{AnyEnergy, Hgo, MooneyRivlin, NeoHookean, Ogden, StrainEnergy};

#[test]
fn toml_tables_for_every_law() {
    let src = r#"
        [[law]]
        law = "neo_hookean"
        mu = 2.0

        [[law]]
        law = "mooney_rivlin"
        c1 = 0.3
        c2 = 0.2

        [[law]]
        law = "ogden"
        terms = [[0.6, 3.0], [-0.1, -2.0]]

        [[law]]
        law = "hgo"
        c = 1.0
        k1 = 0.5
        k2 = 2.0
        theta = 0.5235987755982988
    "#;
    #[derive(serde::Deserialize)]
    struct File {
        law: Vec<AnyEnergy>,
    }
    let f: File = toml::from_str(src).unwrap();
    assert_eq!(
        f.law[0],
        AnyEnergy::NeoHookean(NeoHookean::new(2.0).unwrap())
    );
    assert_eq!(
        f.law[1],
        AnyEnergy::MooneyRivlin(MooneyRivlin::new(0.3, 0.2).unwrap())
    );
    assert_eq!(
        f.law[2],
        AnyEnergy::Ogden(Ogden::new(vec![(0.6, 3.0), (-0.1, -2.0)]).unwrap())
    );
    assert_eq!(
        f.law[3],
        AnyEnergy::Hgo(Hgo::new(1.0, 0.5, 2.0, 0.5235987755982988).unwrap())
    );
    let names: Vec<_> = f.law.iter().map(|l| l.name()).collect();
    assert_eq!(names, ["neo_hookean", "mooney_rivlin", "ogden", "hgo"]);
    for (law, mu) in f.law.iter().zip([2.0, 1.0, 1.0, 1.0]) {
        assert!((law.shear_modulus() - mu).abs() < 1e-15, "{law:?}");
        assert!((law.line(1.0).dsigma - 4.0 * mu).abs() < 1e-12, "{law:?}");
    }
}

#[test]
fn json_round_trip() {
    let law: AnyEnergy = Hgo::new(1.0, 0.5, 2.0, 0.3).unwrap().into();
    let s = serde_json::to_string(&law).unwrap();
    assert_eq!(s, r#"{"law":"hgo","c":1.0,"k1":0.5,"k2":2.0,"theta":0.3}"#);
    let back: AnyEnergy = serde_json::from_str(&s).unwrap();
    assert_eq!(back, law);
    let og: AnyEnergy = Ogden::new(vec![(1.0, 2.0)]).unwrap().into();
    let back: AnyEnergy = serde_json::from_str(&serde_json::to_string(&og).unwrap()).unwrap();
    assert_eq!(back, og);
}

#[test]
fn invalid_input_is_rejected_with_the_field_named() {
    let err = |s: &str| {
        serde_json::from_str::<AnyEnergy>(s)
            .unwrap_err()
            .to_string()
    };
    assert!(err(r#"{"law":"neo_hookean","mu":1.0,"nu":0.5}"#).contains("unknown field `nu`"));
    assert!(err(r#"{"law":"neo_hookean","mu":-1.0}"#).contains("mu = -1 must be finite and > 0"));
    assert!(err(r#"{"law":"hgo","c":1.0,"k1":0.5,"k2":2.0}"#).contains("missing field `theta`"));
    assert!(err(r#"{"law":"hgo","c":1.0,"k1":-0.5,"k2":2.0,"theta":0}"#).contains("k1 = -0.5"));
    assert!(err(r#"{"law":"ogden","terms":[[1.0,-2.0]]}"#).contains("terms[0].mu_p*alpha_p"));
    assert!(err(r#"{"law":"gent","mu":1.0}"#).contains("missing field `jm`"));
    assert!(err(r#"{"law":"yeoh","mu":1.0}"#).contains("unknown variant `yeoh`"));
    assert!(err(r#"{"mu":1.0}"#).contains("missing field `law`"));
    let t = toml::from_str::<AnyEnergy>("law = \"mooney_rivlin\"\nc1 = 0.0\nc2 = 0.0\n");
    assert!(t
        .unwrap_err()
        .to_string()
        .contains("c1 + c2 = 0 must be finite and > 0"));
}
