//! The DXF document structure: header variables, blocks and the entities section, with each
//! entity's groups kept raw. POLYLINE entities own the VERTEX entities that follow them up to
//! SEQEND (and INSERTs their ATTRIBs), so later stages see one entity per drawn object.

use super::tokenizer::Group;

/// One entity (TEXT, POLYLINE, LINE, ...) with its own groups.
#[derive(Debug, Clone, Default)]
pub struct Entity {
    pub kind: String,
    pub line: usize,
    pub groups: Vec<(i32, String)>,
    /// VERTEX children of a POLYLINE, ATTRIB children of an INSERT.
    pub vertices: Vec<Entity>,
}

impl Entity {
    /// The first value of `code`.
    pub fn get(&self, code: i32) -> Option<&str> {
        self.groups.iter().find(|g| g.0 == code).map(|g| g.1.as_str())
    }

    /// The first value of `code` as a number (`None` when missing or not a finite number).
    pub fn num(&self, code: i32) -> Option<f64> {
        self.get(code).and_then(|v| v.parse::<f64>().ok()).filter(|v| v.is_finite())
    }

    /// Every value of `code` parsed as numbers, in order (unparseable ones are skipped).
    pub fn nums(&self, code: i32) -> Vec<f64> {
        self.groups.iter().filter(|g| g.0 == code).filter_map(|g| g.1.parse::<f64>().ok()).collect()
    }

    pub fn layer(&self) -> &str {
        self.get(8).unwrap_or("0")
    }

    /// Text content of TEXT/MTEXT/ATTRIB entities.
    pub fn text(&self) -> Option<&str> {
        matches!(self.kind.as_str(), "TEXT" | "MTEXT" | "ATTRIB" | "ATTDEF").then(|| self.get(1)).flatten()
    }
}

/// A BLOCK definition.
#[derive(Debug, Clone, Default)]
pub struct Block {
    pub name: String,
    pub line: usize,
    pub entities: Vec<Entity>,
}

/// The parts of a DXF file the pattern readers use.
#[derive(Debug, Clone, Default)]
pub struct Document {
    /// Header variables (`$INSUNITS` ...) with their groups.
    pub header: Vec<(String, Vec<(i32, String)>)>,
    pub blocks: Vec<Block>,
    pub entities: Vec<Entity>,
}

impl Document {
    pub fn header_num(&self, var: &str) -> Option<f64> {
        let (_, groups) = self.header.iter().find(|(n, _)| n.eq_ignore_ascii_case(var))?;
        groups.first().and_then(|g| g.1.parse::<f64>().ok()).filter(|v| v.is_finite())
    }

    pub fn block(&self, name: &str) -> Option<&Block> {
        self.blocks.iter().find(|b| b.name == name)
    }
}

/// Builds the document from groups. Unknown sections are skipped; missing ENDSEC/ENDBLK/SEQEND
/// are tolerated (the next structural marker closes what is open), so a single linear pass
/// handles any input and always terminates.
pub fn build(groups: &[Group]) -> Document {
    let mut doc = Document::default();
    let mut section = String::new();
    let mut i = 0;
    while i < groups.len() {
        let g = &groups[i];
        if g.code != 0 {
            if section == "HEADER" && g.code == 9 {
                let name = g.value.clone();
                let mut vals = Vec::new();
                i += 1;
                while i < groups.len() && groups[i].code != 0 && groups[i].code != 9 {
                    vals.push((groups[i].code, groups[i].value.clone()));
                    i += 1;
                }
                doc.header.push((name, vals));
                continue;
            }
            i += 1;
            continue;
        }
        match g.value.as_str() {
            "SECTION" => {
                section =
                    groups.get(i + 1).filter(|n| n.code == 2).map(|n| n.value.to_ascii_uppercase()).unwrap_or_default();
                i += 1;
            }
            "ENDSEC" | "EOF" => {
                section.clear();
                i += 1;
            }
            "BLOCK" if section == "BLOCKS" => {
                let (block, next) = read_block(groups, i);
                doc.blocks.push(block);
                i = next;
            }
            _ if section == "ENTITIES" => {
                let (e, next) = read_entity(groups, i);
                doc.entities.push(e);
                i = next;
            }
            _ => i += 1,
        }
    }
    doc
}

fn read_block(groups: &[Group], start: usize) -> (Block, usize) {
    let (head, mut i) = read_entity(groups, start);
    let mut block = Block { name: head.get(2).unwrap_or("").to_string(), line: head.line, entities: Vec::new() };
    while i < groups.len() {
        match groups[i].value.as_str() {
            "ENDBLK" => {
                // Skip ENDBLK's own groups.
                let (_, next) = read_entity(groups, i);
                return (block, next);
            }
            "ENDSEC" | "EOF" | "BLOCK" => return (block, i),
            _ => {
                let (e, next) = read_entity(groups, i);
                block.entities.push(e);
                i = next;
            }
        }
    }
    (block, i)
}

/// Reads the entity starting at `start` (a code-0 group) and, for POLYLINE, its vertices.
/// Always advances by at least one group.
fn read_entity(groups: &[Group], start: usize) -> (Entity, usize) {
    let mut e =
        Entity { kind: groups[start].value.to_ascii_uppercase(), line: groups[start].line, ..Default::default() };
    let mut i = start + 1;
    while i < groups.len() && groups[i].code != 0 {
        e.groups.push((groups[i].code, groups[i].value.clone()));
        i += 1;
    }
    let child = match e.kind.as_str() {
        "POLYLINE" => "VERTEX",
        "INSERT" => "ATTRIB",
        _ => "",
    };
    if !child.is_empty() {
        while i < groups.len() && groups[i].value.eq_ignore_ascii_case(child) {
            let (v, next) = read_entity(groups, i);
            e.vertices.push(v);
            i = next;
        }
        if i < groups.len() && groups[i].value.eq_ignore_ascii_case("SEQEND") {
            let (_, next) = read_entity(groups, i);
            i = next;
        }
    }
    (e, i)
}
