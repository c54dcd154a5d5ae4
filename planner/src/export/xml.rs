//! A small XML writer over quick-xml for the KML, WPML and ISOXML files: elements opened and
//! closed in order, text and attribute values escaped.

use quick_xml::Writer;
use quick_xml::events::{BytesDecl, BytesEnd, BytesStart, BytesText, Event};

pub struct Xml {
    writer: Writer<Vec<u8>>,
}

impl Xml {
    pub fn new() -> Self {
        let mut writer = Writer::new_with_indent(Vec::new(), b' ', 1);
        writer.write_event(Event::Decl(BytesDecl::new("1.0", Some("UTF-8"), None))).expect("write to memory");
        Xml { writer }
    }

    fn event(&mut self, event: Event<'_>) -> &mut Self {
        // writing to a Vec cannot fail
        self.writer.write_event(event).expect("write to memory");
        self
    }

    pub fn open(&mut self, name: &str, attributes: &[(&str, &str)]) -> &mut Self {
        self.event(Event::Start(BytesStart::new(name).with_attributes(attributes.iter().copied())))
    }

    pub fn close(&mut self, name: &str) -> &mut Self {
        self.event(Event::End(BytesEnd::new(name)))
    }

    /// `<name>text</name>`
    pub fn leaf(&mut self, name: &str, text: &str) -> &mut Self {
        self.open(name, &[]).event(Event::Text(BytesText::new(text))).close(name)
    }

    /// `<name a="…"/>`
    pub fn empty(&mut self, name: &str, attributes: &[(&str, &str)]) -> &mut Self {
        self.event(Event::Empty(BytesStart::new(name).with_attributes(attributes.iter().copied())))
    }

    pub fn finish(self) -> Vec<u8> {
        let mut bytes = self.writer.into_inner();
        bytes.push(b'\n');
        bytes
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_text_and_attributes() {
        let mut x = Xml::new();
        x.open("a", &[("b", "1 < 2 & \"q\"")]).leaf("c", "x < y & z").empty("d", &[]).close("a");
        let text = String::from_utf8(x.finish()).unwrap();
        assert!(text.contains(r#"<a b="1 &lt; 2 &amp; &quot;q&quot;">"#), "{text}");
        assert!(text.contains("<c>x &lt; y &amp; z</c>"), "{text}");
    }
}
